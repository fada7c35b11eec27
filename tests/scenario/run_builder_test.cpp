// Scenarios built into real runs (the project's propagator and loaders): thread-count independence and
// resume bit for bit, refusals before anything runs.
#include <gtest/gtest.h>

#include "core/scenario/run_builder.hpp"

namespace kessler {
namespace {

class Recorder : public EventSink {
 public:
  std::vector<std::pair<std::uint64_t, std::string>> checkpoints;
  std::uint64_t last_seq = 0, events = 0;
  std::int64_t stop_at_step = -1;
  RunControl* control = nullptr;
  void on_encounter(std::uint64_t seq, const Encounter&) override { saw(seq); }
  void on_burn_up(std::uint64_t seq, const BurnUp&) override { saw(seq); }
  void on_progress(std::uint64_t seq, const Progress& p) override {
    saw(seq);
    if (p.step == stop_at_step) control->cancel = true;
  }
  void on_checkpoint(std::uint64_t seq, std::int64_t, const std::string& bytes) override {
    checkpoints.emplace_back(seq, bytes);
  }
  void on_finished(const RunSummary&) override {}
  void on_failed(const std::string&) override {}

 private:
  void saw(std::uint64_t seq) {
    EXPECT_EQ(seq, last_seq + 1) << "sequence numbers must have no gaps";
    last_seq = seq;
    ++events;
  }
};

v1::Scenario leo_subset(const char* extra = "") {
  v1::Scenario s;
  std::string text = std::string(R"(
population: {dataset: leo-19647, max_objects: 1500}
duration_days: 0.02
force_model: {srp: false, atmosphere: exponential_fit}
conjunctions: {enabled: false}
progress_every_steps: 1
checkpoints: {every_steps: 25}
)") + extra;
  auto e = parse_scenario(text, s);
  EXPECT_FALSE(e) << e->message();
  return s;
}

RunSummary run(const v1::Scenario& s, int threads, Recorder& sink, RunControl& control) {
  BuildOptions options;
  options.threads = threads;
  FieldError error;
  auto sim = build_simulation(s, options, &error);
  EXPECT_TRUE(sim) << error.message();
  sink.control = &control;
  return sim->run(sink, control);
}

TEST(RunBuilder, Leo19647RunsAreThreadCountIndependent) {
  auto s = leo_subset();
  Recorder a, b;
  RunControl ca, cb;
  auto one = run(s, 1, a, ca);
  auto two = run(s, 2, b, cb);
  EXPECT_EQ(one.steps, 172);
  EXPECT_EQ(one.objects_initial, 1500u);
  EXPECT_EQ(one.state_digest, two.state_digest);
  EXPECT_EQ(one.events_digest, two.events_digest);
}

TEST(RunBuilder, Leo19647ResumesBitForBit) {
  auto s = leo_subset();
  Recorder whole_sink, first;
  RunControl c1, c2;
  auto whole = run(s, 2, whole_sink, c1);
  first.stop_at_step = 90;
  auto stopped = run(s, 2, first, c2);
  ASSERT_TRUE(stopped.cancelled);
  ASSERT_FALSE(first.checkpoints.empty());
  BuildOptions options;
  options.threads = 1;
  FieldError error;
  auto resumed = resume_simulation(s, first.checkpoints.back().second, options, &error);
  ASSERT_TRUE(resumed) << error.message();
  EXPECT_EQ(resumed->step(), 75);
  Recorder rest;
  rest.last_seq = first.checkpoints.back().first;
  RunControl c3;
  auto finished = resumed->run(rest, c3);
  EXPECT_EQ(finished.state_digest, whole.state_digest);
  EXPECT_EQ(finished.events_digest, whole.events_digest);
  EXPECT_EQ(rest.last_seq, whole_sink.last_seq);
}

TEST(RunBuilder, ACheckpointOfAnotherScenarioIsRefused) {
  auto s = leo_subset();
  Recorder sink;
  sink.stop_at_step = 30;
  RunControl c;
  run(s, 1, sink, c);
  ASSERT_FALSE(sink.checkpoints.empty());
  auto other = leo_subset("dt_s: 5\n");
  FieldError error;
  EXPECT_FALSE(resume_simulation(other, sink.checkpoints.back().second, BuildOptions{}, &error));
  EXPECT_EQ(error.path, "checkpoint");
  EXPECT_NE(error.reason.find("different scenario"), std::string::npos) << error.reason;
  std::string corrupt = sink.checkpoints.back().second;
  corrupt[100] ^= 1;
  EXPECT_FALSE(resume_simulation(s, corrupt, BuildOptions{}, &error));
  EXPECT_EQ(error.message(), "checkpoint: checkpoint: checksum mismatch (corrupt bytes)");
}

TEST(RunBuilder, BadScenariosAreRefusedBeforeAnythingRuns) {
  struct Bad {
    const char* text;
    const char* message;
  };
  for (const Bad& bad : {
           Bad{"population: {dataset: leo-19647}\ndt_s: 0", "dt_s: must be positive, got 0"},
           Bad{"population: {dataset: leo-19647}\ndt_s: -1", "dt_s: must be positive, got -1"},
           Bad{"population: {dataset: leo-19647}\nduration_days: 0.00001",
               "duration_days: the run (0.864 s) is shorter than one step (dt_s = 10 s)"},
       }) {
    v1::Scenario s;
    ASSERT_FALSE(parse_scenario(bad.text, s));
    FieldError error;
    EXPECT_FALSE(build_simulation(s, BuildOptions{}, &error));
    EXPECT_EQ(error.message(), bad.message);
  }
  v1::Scenario s;
  ASSERT_FALSE(parse_scenario("population: {dataset: leo-19647}\nconjunctions: {enabled: false}", s));
  BuildOptions options;
  options.datasets_dir = "/nonexistent";
  FieldError error;
  EXPECT_FALSE(build_simulation(s, options, &error));
  EXPECT_EQ(error.path, "population");
}

}  // namespace
}  // namespace kessler
