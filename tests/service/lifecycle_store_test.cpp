// Lifecycle events (launches, ends of life, disposals) in the daemon's parts: the store keeps them once
// by sequence number in the events and lifecycle_events tables, counts them in the run's statistics,
// removes them with their run, migrates a database of the previous schema, and the relay hands them to
// store and hub in sequence with the other events.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <memory>

#include "server/event_hub.hpp"
#include "server/event_relay.hpp"
#include "server/run_manager.hpp"
#include "server/store.hpp"
#include "tests/service/temp_dir.hpp"

namespace kessler::server {
namespace {

LifecycleReport report(LifecycleEventKind kind, double time_s, ObjectId first, ObjectId last,
                       std::uint64_t row = 0, double altitude_m = 0.0) {
  LifecycleReport r;
  r.kind = kind;
  r.time_s = time_s;
  r.first_id = first;
  r.last_id = last;
  r.row = row;
  r.altitude_m = altitude_m;
  return r;
}

std::shared_ptr<const v1::RunEvent> lifecycle_event(std::int64_t run, std::uint64_t seq,
                                                    const LifecycleReport& r) {
  auto e = std::make_shared<v1::RunEvent>();
  e->set_run_id(run);
  e->set_seq(seq);
  *e->mutable_lifecycle() = to_proto(r);
  return e;
}

// One of each kind: 60 objects launched in two events, two ends of life, a disposal, a failure, a
// de-orbit.
std::vector<LifecycleReport> one_of_each() {
  const ObjectId a = kFirstLaunchId;
  return {report(LifecycleEventKind::kLaunch, 30.0, a, a + 39, 0),
          report(LifecycleEventKind::kLaunch, 60.0, a + 40, a + 59, 2),
          report(LifecycleEventKind::kEndOfLife, 90.0, a + 3, a + 3),
          report(LifecycleEventKind::kDisposal, 90.0, a + 3, a + 3, 0, 412345.5),
          report(LifecycleEventKind::kEndOfLife, 120.0, a + 7, a + 7),
          report(LifecycleEventKind::kDisposalFailed, 120.0, a + 7, a + 7),
          report(LifecycleEventKind::kDeorbit, 150.0, a + 9, a + 9)};
}

void expect_counts(const v1::RunStats& stats) {
  EXPECT_EQ(stats.launches(), 2u);
  EXPECT_EQ(stats.launched_objects(), 60u);
  EXPECT_EQ(stats.ends_of_life(), 2u);
  EXPECT_EQ(stats.disposals(), 1u);
  EXPECT_EQ(stats.disposals_failed(), 1u);
  EXPECT_EQ(stats.deorbits(), 1u);
}

TEST(LifecycleStore, KeepsLifecycleEventsOnceCountsThemAndDropsThemWithTheRun) {
  TempDir dir;
  Store store(dir.path() + "/k.db");
  const std::int64_t id = store.create_run(v1::Scenario(), 1, 0.0);
  const std::vector<LifecycleReport> reports = one_of_each();
  for (std::size_t i = 0; i < reports.size(); ++i) store.append_event(lifecycle_event(id, i + 1, reports[i]));
  // A resumed run re-emits events with the same numbers: nothing is stored or counted twice.
  store.append_event(lifecycle_event(id, 1, reports[0]));
  store.append_event(lifecycle_event(id, 4, reports[3]));
  store.flush();

  const auto events = store.read_events(id, 0, 100, true);
  ASSERT_EQ(events.size(), reports.size());
  for (std::size_t i = 0; i < events.size(); ++i) {
    ASSERT_TRUE(events[i].has_lifecycle()) << i;
    EXPECT_EQ(events[i].seq(), i + 1);
    EXPECT_EQ(events[i].lifecycle().SerializeAsString(), to_proto(reports[i]).SerializeAsString()) << i;
  }
  EXPECT_EQ(events[0].lifecycle().kind(), v1::LIFECYCLE_KIND_LAUNCH);
  EXPECT_EQ(events[1].lifecycle().row(), 2u);
  EXPECT_EQ(events[3].lifecycle().kind(), v1::LIFECYCLE_KIND_DISPOSAL);
  EXPECT_DOUBLE_EQ(events[3].lifecycle().altitude_m(), 412345.5);
  EXPECT_EQ(events[5].lifecycle().kind(), v1::LIFECYCLE_KIND_DISPOSAL_FAILED);
  EXPECT_EQ(events[6].lifecycle().kind(), v1::LIFECYCLE_KIND_DEORBIT);

  v1::GetRunStatsRequest request;
  request.set_run_id(id);
  expect_counts(store.run_stats(request, 200.0));

  EXPECT_TRUE(store.delete_run(id));
  const v1::RunStats after = store.run_stats(request, 200.0);
  EXPECT_EQ(after.launches(), 0u);
  EXPECT_EQ(after.ends_of_life(), 0u);
}

// The schema of version 3, as a daemon before lifecycle events left it (version 2 and the breakups).
const char* const kSchemaV3 = R"sql(
  CREATE TABLE runs (id INTEGER PRIMARY KEY AUTOINCREMENT, name TEXT NOT NULL, state INTEGER NOT NULL,
    scenario BLOB NOT NULL, threads INTEGER NOT NULL, created_unix_s REAL NOT NULL,
    started_unix_s REAL NOT NULL DEFAULT 0, finished_unix_s REAL NOT NULL DEFAULT 0,
    error TEXT NOT NULL DEFAULT '', summary BLOB);
  CREATE INDEX runs_by_state ON runs(state, id);
  CREATE TABLE events (run_id INTEGER NOT NULL, seq INTEGER NOT NULL, kind INTEGER NOT NULL,
    payload BLOB NOT NULL, id1 INTEGER, id2 INTEGER, tca_s REAL, miss_distance_m REAL, kappa REAL,
    encounter_kind INTEGER, PRIMARY KEY (run_id, seq)) WITHOUT ROWID;
  CREATE INDEX encounters_by_pair ON events(run_id, id1, id2, miss_distance_m) WHERE kind = 2;
  CREATE TABLE checkpoints (run_id INTEGER PRIMARY KEY, last_seq INTEGER NOT NULL, step INTEGER NOT NULL,
    bytes BLOB NOT NULL);
  ALTER TABLE runs ADD COLUMN ingest BLOB;
  CREATE TABLE object_names (run_id INTEGER NOT NULL, object_id INTEGER NOT NULL, name TEXT NOT NULL,
    PRIMARY KEY (run_id, object_id)) WITHOUT ROWID;
  CREATE TABLE breakups (run_id INTEGER NOT NULL, breakup_id INTEGER NOT NULL, seq INTEGER NOT NULL,
    time_s REAL NOT NULL, kind INTEGER NOT NULL, source INTEGER NOT NULL, catastrophic INTEGER NOT NULL,
    fragment_count INTEGER NOT NULL, first_id INTEGER NOT NULL, last_id INTEGER NOT NULL,
    remnant_id INTEGER NOT NULL, PRIMARY KEY (run_id, breakup_id)) WITHOUT ROWID;
  CREATE TABLE fragments (run_id INTEGER NOT NULL, fragment_id INTEGER NOT NULL, breakup_id INTEGER NOT NULL,
    parent_id INTEGER NOT NULL, characteristic_length_m REAL NOT NULL, area_to_mass_m2_kg REAL NOT NULL,
    mass_kg REAL NOT NULL, delta_v_m_s REAL NOT NULL, PRIMARY KEY (run_id, fragment_id)) WITHOUT ROWID;
  CREATE INDEX fragments_by_breakup ON fragments(run_id, breakup_id, fragment_id);
  INSERT INTO runs(name, state, scenario, threads, created_unix_s) VALUES('old', 3, X'', 1, 5.0);
  INSERT INTO events(run_id, seq, kind, payload) VALUES(1, 1, 3, X'');
  PRAGMA user_version = 3;
)sql";

TEST(LifecycleStore, MigratesADatabaseOfTheVersionBefore) {
  TempDir dir;
  const std::string path = dir.path() + "/old.db";
  {
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
    char* message = nullptr;
    ASSERT_EQ(sqlite3_exec(db, kSchemaV3, nullptr, nullptr, &message), SQLITE_OK) << (message ? message : "");
    sqlite3_close(db);
  }
  Store store(path);
  EXPECT_GE(Store::kSchemaVersion, 4);
  EXPECT_EQ(store.schema_version(), Store::kSchemaVersion);
  auto run = store.get_run(1);
  ASSERT_TRUE(run);
  EXPECT_EQ(run->name(), "old");
  EXPECT_EQ(store.max_seq(1), 1u);  // the old run's events stay
  const std::vector<LifecycleReport> reports = one_of_each();
  for (std::size_t i = 0; i < reports.size(); ++i) store.append_event(lifecycle_event(1, i + 2, reports[i]));
  store.flush();
  v1::GetRunStatsRequest request;
  request.set_run_id(1);
  expect_counts(store.run_stats(request, 200.0));
}

TEST(LifecycleRelay, HandsLifecycleEventsToStoreAndHubInSequence) {
  TempDir dir;
  Store store(dir.path() + "/k.db");
  const std::int64_t id = store.create_run(v1::Scenario(), 1, 0.0);
  EventHub hub;
  const std::vector<LifecycleReport> reports = one_of_each();
  {
    EventRelay relay(id, hub, store, std::chrono::milliseconds(1));
    BurnUp burn_up;
    burn_up.id = 9;
    relay.on_burn_up(1, burn_up);
    for (std::size_t i = 0; i < reports.size(); ++i) relay.on_lifecycle(i + 2, reports[i]);
    Progress progress;
    progress.objects_alive = 111;
    relay.on_progress(reports.size() + 2, progress);
    relay.drain();
  }
  store.flush();
  auto read = hub.read_after(0, 100);
  ASSERT_EQ(read.events.size(), reports.size() + 2);
  for (std::size_t i = 0; i < read.events.size(); ++i) EXPECT_EQ(read.events[i]->seq(), i + 1);
  EXPECT_TRUE(read.events[0]->has_burn_up());
  for (std::size_t i = 0; i < reports.size(); ++i) {
    ASSERT_TRUE(read.events[i + 1]->has_lifecycle());
    EXPECT_EQ(read.events[i + 1]->lifecycle().first_id(), reports[i].first_id);
    EXPECT_EQ(static_cast<int>(read.events[i + 1]->lifecycle().kind()), static_cast<int>(reports[i].kind));
  }
  EXPECT_TRUE(read.events.back()->has_progress());
  auto stored = store.read_events(id, 0, 100);
  ASSERT_EQ(stored.size(), read.events.size());
  for (std::size_t i = 0; i < stored.size(); ++i)
    EXPECT_EQ(stored[i].SerializeAsString(), read.events[i]->SerializeAsString());
  v1::GetRunStatsRequest request;
  request.set_run_id(id);
  expect_counts(store.run_stats(request, 200.0));
}

}  // namespace
}  // namespace kessler::server
