// The event stream (kessler-mpi --event-stream to kesslerd): every EventSink call written as a record and
// replayed into another sink arrives whole, in order, bit for bit; a failure or a stream cut short fails
// the replay as Simulation::run fails.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/simulation/event_stream.hpp"

namespace kessler {
namespace {

// Each call as a line, doubles in hex: equal lines, equal bits.
class RecordingSink final : public EventSink {
 public:
  std::vector<std::string> calls;
  void on_encounter(std::uint64_t seq, const Encounter& e) override {
    std::ostringstream line;
    line << std::hexfloat << "encounter " << seq;
    for_each_field(e, [&](const char* name, const auto& value) {
      using T = std::remove_cvref_t<decltype(value)>;
      if constexpr (std::is_same_v<T, Eigen::Vector3d>)
        line << ' ' << name << '=' << value.x() << ',' << value.y() << ',' << value.z();
      else if constexpr (std::is_enum_v<T>)
        line << ' ' << name << '=' << static_cast<int>(value);
      else
        line << ' ' << name << '=' << value;
    });
    calls.push_back(line.str());
  }
  void on_burn_up(std::uint64_t seq, const BurnUp& b) override {
    add("burn_up", seq, b.id, b.time_s, b.altitude_m);
  }
  void on_progress(std::uint64_t seq, const Progress& p) override {
    add("progress", seq, p.step, p.total_steps, p.sim_time_s, p.objects_alive, p.objects_by_type.fragments,
        p.events_so_far, p.wall_s, p.eta_s);
  }
  void on_breakup(std::uint64_t seq, const BreakupReport& b) override {
    add("breakup", seq, b.breakup_id, static_cast<int>(b.source), b.event_index, b.time_s,
        static_cast<int>(b.kind), b.parents.size(), b.parents.back(), b.catastrophic,
        b.specific_energy_j_per_g, b.fragment_count, b.fragment_mass_kg, b.first_id, b.last_id, b.remnant_id,
        b.fragments.size(), b.fragments.back().id, b.fragments.back().delta_v_m_s);
  }
  void on_lifecycle(std::uint64_t seq, const LifecycleReport& l) override {
    add("lifecycle", seq, static_cast<int>(l.kind), l.time_s, l.first_id, l.last_id, l.row, l.altitude_m);
  }
  void on_snapshot(const std::shared_ptr<const PopulationSnapshot>& s) override {
    add("snapshot", s->step, s->sim_time_s, s->size(), s->id.back(), static_cast<int>(s->status.back()),
        s->mean_anomaly_rad.back());
  }
  void on_checkpoint(std::uint64_t last_seq, std::int64_t step, const std::string& bytes) override {
    add("checkpoint", last_seq, step, bytes);
  }
  void on_finished(const RunSummary& s) override {
    add("finished", s.events, s.conjunctions, s.steps, s.sim_time_s, s.events_digest, s.state_digest,
        s.timers.total_s, s.cancelled);
  }
  void on_failed(const std::string& reason) override { add("failed", reason); }

 private:
  template <class... A>
  void add(const char* what, const A&... values) {
    std::ostringstream line;
    line << std::hexfloat << what;
    ((line << ' ' << values), ...);
    calls.push_back(line.str());
  }
};

// The records written by `write` into a file, replayed into `into`.
RunSummary round_trip(const std::function<void(EventStreamWriter&)>& write, RecordingSink& into,
                      const std::string& ended_early = "cut off") {
  std::FILE* file = std::tmpfile();
  EventStreamWriter writer(fileno(file));
  write(writer);
  ::lseek(fileno(file), 0, SEEK_SET);
  struct Close {
    std::FILE* f;
    ~Close() { std::fclose(f); }
  } close{file};
  return replay_event_stream(fileno(file), into, [&] { return ended_early; });
}

TEST(EventStream, EveryKindOfRecordArrivesWholeAndInOrder) {
  Encounter e;
  e.id1 = 7, e.id2 = 1'000'000'000'001, e.tca_s = 0.1 + 0.2, e.miss_distance_m = 1e-300, e.kappa = 3.5;
  e.kind = EncounterKind::kCollision;
  e.r1_m = {1.0 / 3, -2.0, 6.7e6}, e.v1_m_s = {1, 2, 3}, e.r2_m = {4, 5, 6}, e.v2_m_s = {-7.5, 8, 9};
  BreakupReport b;
  b.breakup_id = 2, b.source = BreakupSource::kCollision, b.time_s = 12.25, b.kind = BreakupKind::kCollision;
  b.parents = {3, 4}, b.catastrophic = true, b.fragment_count = 2, b.first_id = 10, b.last_id = 11;
  b.fragments = {FragmentReport{10, 3, 0.1, 0.2, 0.3, 0.4}, FragmentReport{11, 4, 0.5, 0.6, 0.7, 8.25}};
  auto snapshot = std::make_shared<PopulationSnapshot>();
  snapshot->step = 8, snapshot->sim_time_s = 240;
  snapshot->resize(3);
  snapshot->id = {1, 2, 99}, snapshot->mean_anomaly_rad[2] = 1.5f;
  std::string checkpoint("\0binary\xff bytes", 14);
  RunSummary summary;
  summary.events = 5, summary.conjunctions = 1, summary.steps = 8, summary.sim_time_s = 240.5;
  summary.events_digest = "ab01", summary.state_digest = "cd02", summary.timers.total_s = 0.125;

  auto write_all = [&](EventSink& sink) {
    sink.on_encounter(1, e);
    sink.on_burn_up(2, BurnUp{5, 30.5, -1.0});
    sink.on_breakup(3, b);
    sink.on_lifecycle(4, LifecycleReport{LifecycleEventKind::kDisposal, 60, 8, 8, 0, 4.5e5});
    sink.on_progress(5, Progress{8, 16, 240, 2999, {1, 2, 3, 4, 5}, 4, 0.01, 0.02});
    sink.on_snapshot(snapshot);
    sink.on_checkpoint(5, 8, checkpoint);
    sink.on_finished(summary);
  };
  RecordingSink direct, replayed;
  write_all(direct);
  const RunSummary got = round_trip(
      [&](EventStreamWriter& w) {
        write_all(w);
        w.write_summary(summary);
      },
      replayed);
  EXPECT_EQ(replayed.calls, direct.calls);
  ASSERT_EQ(replayed.calls.size(), 8u);
  EXPECT_EQ(got.events_digest, "ab01");
  EXPECT_EQ(got.sim_time_s, 240.5);
}

TEST(EventStream, AStopAtACheckpointEndsWithoutOnFinished) {
  RunSummary summary;
  summary.cancelled = summary.stopped_at_checkpoint = true;
  RecordingSink replayed;
  const RunSummary got = round_trip([&](EventStreamWriter& w) { w.write_summary(summary); }, replayed);
  EXPECT_TRUE(got.stopped_at_checkpoint);
  EXPECT_TRUE(got.cancelled);
  EXPECT_TRUE(replayed.calls.empty());
}

TEST(EventStream, AFailureRecordFailsTheReplayWithItsReason) {
  RecordingSink replayed;
  try {
    round_trip(
        [&](EventStreamWriter& w) {
          w.on_burn_up(1, BurnUp{5, 30.5, -1.0});
          w.on_failed("rank 1: object 12 has no elements");
        },
        replayed);
    FAIL() << "no throw";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "rank 1: object 12 has no elements");
  }
  ASSERT_EQ(replayed.calls.size(), 2u);
  EXPECT_EQ(replayed.calls[1], "failed rank 1: object 12 has no elements");
}

TEST(EventStream, AStreamCutShortFailsTheReplayWithWhatEndedIt) {
  RecordingSink replayed;
  EXPECT_THROW(round_trip(
                   [&](EventStreamWriter& w) {
                     w.on_burn_up(1, BurnUp{5, 30.5, -1.0});
                   },
                   replayed, "the MPI job ended (exit status 137)"),
               std::runtime_error);
  ASSERT_EQ(replayed.calls.size(), 2u);
  EXPECT_EQ(replayed.calls[1], "failed the MPI job ended (exit status 137)");
}

TEST(EventStream, AStreamCutInsideARecordNamesWhatEndedItFirst) {
  std::FILE* file = std::tmpfile();
  EventStreamWriter writer(fileno(file));
  writer.on_burn_up(1, BurnUp{5, 30.5, -1.0});
  const off_t whole = ::lseek(fileno(file), 0, SEEK_CUR);
  ASSERT_EQ(::ftruncate(fileno(file), whole - 3), 0);
  ::lseek(fileno(file), 0, SEEK_SET);
  RecordingSink replayed;
  try {
    replay_event_stream(fileno(file), replayed,
                        [] { return std::string("the MPI job ended (exit status 137)"); });
    ADD_FAILURE() << "no throw";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "the MPI job ended (exit status 137); event stream: cut off inside a record");
  }
  std::fclose(file);
  ASSERT_EQ(replayed.calls.size(), 1u);
  EXPECT_EQ(replayed.calls[0],
            "failed the MPI job ended (exit status 137); event stream: cut off inside a record");
}

}  // namespace
}  // namespace kessler
