// The store on its own: schema, runs, idempotent event storage, checkpoints after their events,
// conjunction queries, and a throughput run as a correctness test (no timing assertion).
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <random>
#include <thread>

#include "server/store.hpp"
#include "tests/service/temp_dir.hpp"

namespace kessler::server {
namespace {

std::shared_ptr<const v1::RunEvent> encounter_event(std::int64_t run, std::uint64_t seq, std::uint64_t id1,
                                                    std::uint64_t id2, double tca_s, double miss_m,
                                                    double kappa,
                                                    v1::EncounterKind kind = v1::ENCOUNTER_KIND_CONJUNCTION) {
  auto e = std::make_shared<v1::RunEvent>();
  e->set_run_id(run);
  e->set_seq(seq);
  auto* c = e->mutable_encounter();
  c->set_id1(id1);
  c->set_id2(id2);
  c->set_tca_s(tca_s);
  c->set_miss_distance_m(miss_m);
  c->set_kappa(kappa);
  c->set_kind(kind);
  c->set_seq(seq);
  return e;
}

std::shared_ptr<const v1::RunEvent> progress_event(std::int64_t run, std::uint64_t seq, double t,
                                                   std::uint64_t alive) {
  auto e = std::make_shared<v1::RunEvent>();
  e->set_run_id(run);
  e->set_seq(seq);
  e->mutable_progress()->set_sim_time_s(t);
  e->mutable_progress()->set_objects_alive(alive);
  return e;
}

TEST(Store, KeepsTheIngestReportAndNamesTheObjectsOfConjunctions) {
  TempDir dir;
  Store store(dir.path() + "/k.db");
  const std::int64_t id = store.create_run(v1::Scenario(), 1, 1000.0);
  EXPECT_FALSE(store.get_run(id)->has_ingest());
  v1::IngestReport report;
  report.set_records(10);
  report.set_kept(7);
  auto* drop = report.add_dropped();
  drop->set_reason("excluded name");
  drop->set_count(3);
  store.set_ingest(id, report);
  EXPECT_EQ(store.get_run(id)->ingest().SerializeAsString(), report.SerializeAsString());
  EXPECT_EQ(store.list_runs({}, 10, "").items.front().ingest().kept(), 7u);

  store.set_object_names(id, {{5, "TIROS 1"}, {9, ""}});
  store.set_object_names(id, {{5, "RENAMED"}});  // the first names stay
  store.append_event(encounter_event(id, 1, 5, 9, 10.0, 100.0, 0.5));
  store.flush();
  v1::ListConjunctionsRequest request;
  request.set_run_id(id);
  auto page = store.list_conjunctions(request);
  ASSERT_EQ(page.items.size(), 1u);
  EXPECT_EQ(page.items[0].name1(), "TIROS 1");
  EXPECT_EQ(page.items[0].name2(), "");
  EXPECT_EQ(store.object_names(id).size(), 1u);
  EXPECT_TRUE(store.delete_run(id));
  EXPECT_TRUE(store.object_names(id).empty());
}

TEST(Store, CreatesSchemaAndKeepsRunsAcrossReopen) {
  TempDir dir;
  std::string path = dir.path() + "/k.db";
  std::int64_t id = 0;
  {
    Store store(path);
    EXPECT_EQ(store.schema_version(), Store::kSchemaVersion);
    v1::Scenario scenario;
    scenario.set_name("tiny");
    scenario.set_duration_days(0.5);
    id = store.create_run(scenario, 2, 1000.0);
    store.append_event(progress_event(id, 1, 10.0, 5));
    store.flush();
    v1::RunSummary summary;
    summary.set_events(1);
    summary.set_events_digest("abc");
    store.set_finished(id, v1::RUN_STATE_SUCCEEDED, 1001.0, "", &summary);
  }
  Store store(path);
  auto run = store.get_run(id);
  ASSERT_TRUE(run);
  EXPECT_EQ(run->name(), "tiny");
  EXPECT_EQ(run->state(), v1::RUN_STATE_SUCCEEDED);
  EXPECT_EQ(run->threads(), 2);
  EXPECT_DOUBLE_EQ(run->scenario().duration_days(), 0.5);
  EXPECT_EQ(run->summary().events_digest(), "abc");
  EXPECT_EQ(run->last_seq(), 1u);
  EXPECT_DOUBLE_EQ(run->progress().sim_time_s(), 10.0);
  EXPECT_FALSE(store.get_run(id + 1));
}

TEST(Store, RefusesADatabaseFromANewerVersion) {
  TempDir dir;
  std::string path = dir.path() + "/k.db";
  { Store store(path); }
  {
    // Simulate a newer daemon having migrated the file.
    Store store(path);
    store.flush();
  }
  std::string cmd = "sqlite3 " + path + " 'PRAGMA user_version = 99' 2>/dev/null";
  if (std::system(cmd.c_str()) != 0) GTEST_SKIP() << "sqlite3 shell not available";
  EXPECT_THROW(Store store(path), StoreError);
}

TEST(Store, StoresEventsIdempotentlyBySequence) {
  TempDir dir;
  Store store(dir.path() + "/k.db");
  std::int64_t id = store.create_run(v1::Scenario(), 0, 0.0);
  for (std::uint64_t s = 1; s <= 10; ++s)
    store.append_event(encounter_event(id, s, s, s + 1, s * 1.0, 1.0, 0.5));
  // A resumed run re-emits 6..10 with the same numbers: the first copy stays.
  for (std::uint64_t s = 6; s <= 12; ++s)
    store.append_event(encounter_event(id, s, s, s + 1, s * 1.0, 2.0, 0.5));
  store.flush();
  auto events = store.read_events(id, 0, 100);
  ASSERT_EQ(events.size(), 12u);
  for (std::size_t i = 0; i < events.size(); ++i) EXPECT_EQ(events[i].seq(), i + 1);
  EXPECT_DOUBLE_EQ(events[7].encounter().miss_distance_m(), 1.0);
  EXPECT_DOUBLE_EQ(events[11].encounter().miss_distance_m(), 2.0);
  auto tail = store.read_events(id, 9, 2);
  ASSERT_EQ(tail.size(), 2u);
  EXPECT_EQ(tail[0].seq(), 10u);
  EXPECT_EQ(store.max_seq(id), 12u);
}

TEST(Store, CheckpointIsStoredAfterItsEvents) {
  TempDir dir;
  Store store(dir.path() + "/k.db");
  std::int64_t id = store.create_run(v1::Scenario(), 0, 0.0);
  for (std::uint64_t s = 1; s <= 5000; ++s) store.append_event(progress_event(id, s, s, 1));
  store.append_checkpoint(id, 5000, 50, std::string("state\0bytes", 11));
  store.flush();
  auto cp = store.latest_checkpoint(id);
  ASSERT_TRUE(cp);
  EXPECT_EQ(cp->last_seq, 5000u);
  EXPECT_EQ(cp->step, 50);
  EXPECT_EQ(cp->bytes, std::string("state\0bytes", 11));
  EXPECT_GE(store.max_seq(id), cp->last_seq);
  // An older checkpoint (a resumed run repeating one) never replaces a newer one.
  store.append_checkpoint(id, 100, 10, "old");
  store.flush();
  EXPECT_EQ(store.latest_checkpoint(id)->step, 50);
}

// With a minimum interval between a run's checkpoint writes, the first is written at once, later ones
// wait; a newer one replaces a waiting one unwritten (an older one never does), and flush() writes
// the one waiting, unless the run ended first. Events are not held back.
TEST(Store, CheckpointsWaitForTheirIntervalAndTheNewestWaitingOneIsWritten) {
  TempDir dir;
  Store store(dir.path() + "/k.db", std::chrono::hours(1));
  std::int64_t id = store.create_run(v1::Scenario(), 0, 0.0);
  store.append_event(progress_event(id, 1, 1, 1));
  store.append_checkpoint(id, 1, 10, "ten");
  // The first of the run is due at once: it is written without a flush.
  auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (!store.latest_checkpoint(id) && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  ASSERT_TRUE(store.latest_checkpoint(id));
  EXPECT_EQ(store.latest_checkpoint(id)->bytes, "ten");
  store.append_event(progress_event(id, 2, 2, 1));
  store.append_checkpoint(id, 2, 20, "twenty");
  store.append_event(progress_event(id, 3, 3, 1));
  store.append_checkpoint(id, 3, 30, "thirty");
  store.append_checkpoint(id, 3, 25, "older");  // a resumed run repeating an older one
  store.append_event(progress_event(id, 4, 4, 1));
  // The events go in; the checkpoints wait (an hour).
  while (store.max_seq(id) < 4 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  EXPECT_EQ(store.max_seq(id), 4u);
  EXPECT_EQ(store.latest_checkpoint(id)->step, 10);
  store.flush();
  auto cp = store.latest_checkpoint(id);
  ASSERT_TRUE(cp);
  EXPECT_EQ(cp->step, 30);
  EXPECT_EQ(cp->last_seq, 3u);
  EXPECT_EQ(cp->bytes, "thirty");
  // A run that ended drops its waiting checkpoint unwritten; the stored one stays.
  store.append_checkpoint(id, 4, 40, "forty");
  store.discard_waiting_checkpoint(id);
  store.flush();
  EXPECT_EQ(store.latest_checkpoint(id)->step, 30);
}

TEST(Store, QueriesConjunctionsWithFiltersPagesAndClosestPerPair) {
  TempDir dir;
  Store store(dir.path() + "/k.db");
  std::int64_t id = store.create_run(v1::Scenario(), 0, 0.0);
  std::int64_t other = store.create_run(v1::Scenario(), 0, 0.0);
  store.append_event(encounter_event(id, 1, 1, 2, 100.0, 50.0, 5.0));
  store.append_event(encounter_event(id, 2, 1, 2, 200.0, 20.0, 2.0));  // closest of pair (1,2)
  store.append_event(encounter_event(id, 3, 3, 4, 300.0, 1.0, 0.5, v1::ENCOUNTER_KIND_COLLISION));
  store.append_event(encounter_event(id, 4, 2, 5, 400.0, 80.0, 8.0));
  store.append_event(encounter_event(id, 5, 6, 7, 500.0, 10.0, 1.0, v1::ENCOUNTER_KIND_EVASION));
  store.append_event(progress_event(id, 6, 500.0, 7));
  store.append_event(encounter_event(other, 1, 1, 2, 1.0, 1.0, 0.1));
  store.flush();

  auto seqs = [&](const v1::ListConjunctionsRequest& r) {
    std::vector<std::uint64_t> out;
    for (const auto& c : store.list_conjunctions(r).items) out.push_back(c.seq());
    return out;
  };
  v1::ListConjunctionsRequest r;
  r.set_run_id(id);
  EXPECT_EQ(seqs(r), (std::vector<std::uint64_t>{1, 2, 3, 4}));
  r.set_include_evasions(true);
  EXPECT_EQ(seqs(r), (std::vector<std::uint64_t>{1, 2, 3, 4, 5}));
  r.set_include_evasions(false);
  r.set_kappa_min(1.0);
  r.set_kappa_max(5.0);
  EXPECT_EQ(seqs(r), (std::vector<std::uint64_t>{1, 2}));
  r.clear_kappa_min();
  r.clear_kappa_max();
  r.set_object_id(2);
  EXPECT_EQ(seqs(r), (std::vector<std::uint64_t>{1, 2, 4}));
  r.clear_object_id();
  r.set_time_min_s(150.0);
  r.set_time_max_s(350.0);
  EXPECT_EQ(seqs(r), (std::vector<std::uint64_t>{2, 3}));
  r.clear_time_min_s();
  r.clear_time_max_s();
  r.set_collisions_only(true);
  EXPECT_EQ(seqs(r), (std::vector<std::uint64_t>{3}));
  r.set_collisions_only(false);
  r.set_closest_per_pair(true);
  EXPECT_EQ(seqs(r), (std::vector<std::uint64_t>{2, 3, 4}));
  r.set_closest_per_pair(false);

  // Pages of two.
  r.set_page_size(2);
  auto first = store.list_conjunctions(r);
  EXPECT_EQ(first.total, 4u);
  ASSERT_EQ(first.items.size(), 2u);
  ASSERT_FALSE(first.next_token.empty());
  r.set_page_token(first.next_token);
  auto second = store.list_conjunctions(r);
  ASSERT_EQ(second.items.size(), 2u);
  EXPECT_EQ(second.items[0].seq(), 3u);
  EXPECT_TRUE(second.next_token.empty());
  r.set_page_token("garbage");
  EXPECT_THROW(store.list_conjunctions(r), std::invalid_argument);
}

TEST(Store, StatsCountByKappaOverTime) {
  TempDir dir;
  Store store(dir.path() + "/k.db");
  std::int64_t id = store.create_run(v1::Scenario(), 0, 0.0);
  store.append_event(encounter_event(id, 1, 1, 2, 10.0, 5.0, 0.5));
  store.append_event(encounter_event(id, 2, 1, 3, 20.0, 5.0, 3.0));
  store.append_event(encounter_event(id, 3, 1, 4, 150.0, 5.0, 0.8, v1::ENCOUNTER_KIND_COLLISION));
  store.append_event(encounter_event(id, 4, 1, 5, 150.0, 5.0, 0.8, v1::ENCOUNTER_KIND_EVASION));
  store.append_event(progress_event(id, 5, 100.0, 9));
  store.append_event(progress_event(id, 6, 200.0, 8));
  store.flush();
  v1::GetRunStatsRequest r;
  r.set_run_id(id);
  r.set_time_bin_s(100.0);
  r.add_kappas(1.0);
  r.add_kappas(5.0);
  auto stats = store.run_stats(r, 200.0);
  ASSERT_EQ(stats.bin_start_s_size(), 2);
  ASSERT_EQ(stats.by_kappa_size(), 2);
  EXPECT_EQ(stats.by_kappa(0).per_bin(0), 1u);  // kappa <= 1: seq 1 in bin 0, seq 3 in bin 1
  EXPECT_EQ(stats.by_kappa(0).per_bin(1), 1u);
  EXPECT_EQ(stats.by_kappa(1).cumulative(1), 3u);  // evasions do not count
  EXPECT_EQ(stats.conjunctions(), 3u);
  EXPECT_EQ(stats.collisions(), 1u);
  EXPECT_EQ(stats.evasions(), 1u);
  ASSERT_EQ(stats.objects_alive_size(), 2);
  EXPECT_EQ(stats.objects_alive(1).objects_alive(), 8u);
}

TEST(Store, DeletesARunWithEverythingStoredForIt) {
  TempDir dir;
  Store store(dir.path() + "/k.db");
  std::int64_t id = store.create_run(v1::Scenario(), 0, 0.0);
  store.append_event(encounter_event(id, 1, 1, 2, 10.0, 5.0, 0.5));
  store.append_checkpoint(id, 1, 1, "x");
  EXPECT_TRUE(store.delete_run(id));
  EXPECT_FALSE(store.get_run(id));
  EXPECT_TRUE(store.read_events(id, 0, 10).empty());
  EXPECT_FALSE(store.latest_checkpoint(id));
  EXPECT_FALSE(store.delete_run(id));
}

TEST(Store, ListsRunsNewestFirstByStateInPages) {
  TempDir dir;
  Store store(dir.path() + "/k.db");
  std::vector<std::int64_t> ids;
  for (int i = 0; i < 5; ++i) ids.push_back(store.create_run(v1::Scenario(), 0, i));
  store.set_finished(ids[1], v1::RUN_STATE_FAILED, 9.0, "boom", nullptr);
  store.set_running(ids[3], 9.0);
  auto all = store.list_runs({}, 3, "");
  ASSERT_EQ(all.items.size(), 3u);
  EXPECT_EQ(all.items[0].id(), ids[4]);
  auto rest = store.list_runs({}, 3, all.next_token);
  ASSERT_EQ(rest.items.size(), 2u);
  EXPECT_EQ(rest.items[1].id(), ids[0]);
  EXPECT_TRUE(rest.next_token.empty());
  auto failed = store.list_runs({v1::RUN_STATE_FAILED}, 10, "");
  ASSERT_EQ(failed.items.size(), 1u);
  EXPECT_EQ(failed.items[0].error(), "boom");
  EXPECT_EQ(store.runs_in_state(v1::RUN_STATE_RUNNING), (std::vector<std::int64_t>{ids[3]}));
}

// Correctness under volume: a quarter million events in, every one back, in order, none twice.
TEST(Store, TakesAQuarterMillionEventsAndReturnsEachOnce) {
  TempDir dir;
  Store store(dir.path() + "/k.db");
  std::int64_t id = store.create_run(v1::Scenario(), 0, 0.0);
  const std::uint64_t n = 250000;
  auto start = std::chrono::steady_clock::now();
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> kappa(0.0, 10.0);
  for (std::uint64_t s = 1; s <= n; ++s) {
    if (s % 100 == 0)
      store.append_event(progress_event(id, s, s * 1.0, 1000));
    else
      store.append_event(encounter_event(id, s, s % 997, 1000 + s % 991, s * 0.1, 10.0, kappa(rng)));
  }
  auto t0 = std::chrono::steady_clock::now();
  store.flush();
  double flush_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("stored %llu events, flush waited %.2f s\n", static_cast<unsigned long long>(n), flush_s);
  EXPECT_EQ(store.events_written(), n);
  EXPECT_EQ(store.max_seq(id), n);
  std::uint64_t cursor = 0, count = 0;
  for (;;) {
    auto events = store.read_events(id, cursor, 50000);
    if (events.empty()) break;
    for (const auto& e : events) {
      ASSERT_EQ(e.seq(), cursor + 1);
      cursor = e.seq();
      ++count;
    }
  }
  EXPECT_EQ(count, n);
  std::printf("append+store %.2f s\n", std::chrono::duration<double>(t0 - start).count() + flush_s);
  v1::ListConjunctionsRequest r;
  r.set_run_id(id);
  r.set_page_size(1);
  EXPECT_EQ(store.list_conjunctions(r).total, n - n / 100);
}

}  // namespace
}  // namespace kessler::server
