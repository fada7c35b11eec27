// Breakups in the daemon's parts: the store keeps breakup events with their fragments (idempotently by
// sequence number, listed by fragment id in pages, removed with their run), migrates a database of the
// previous schema, and the relay hands breakups to store and hub in sequence with the other events.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <memory>
#include <stdexcept>

#include "server/event_hub.hpp"
#include "server/event_relay.hpp"
#include "server/run_manager.hpp"
#include "server/store.hpp"
#include "tests/service/temp_dir.hpp"

namespace kessler::server {
namespace {

BreakupReport explosion_report(BreakupId breakup_id, ObjectId parent, ObjectId first_id,
                               std::uint64_t count) {
  BreakupReport b;
  b.breakup_id = breakup_id;
  b.source = BreakupSource::kScheduled;
  b.time_s = 30.0 * breakup_id;
  b.kind = BreakupKind::kExplosion;
  b.parents = {parent};
  b.catastrophic = true;
  b.fragment_count = count;
  b.first_id = first_id;
  b.last_id = first_id + count - 1;
  for (std::uint64_t i = 0; i < count; ++i) {
    FragmentReport f;
    f.id = first_id + i;
    f.parent_id = parent;
    f.characteristic_length_m = 0.1 + 0.01 * static_cast<double>(i);
    f.area_to_mass_m2_kg = 0.05;
    f.mass_kg = 0.5 + static_cast<double>(i);
    f.delta_v_m_s = 10.0 + static_cast<double>(i);
    b.fragment_mass_kg += f.mass_kg;
    b.fragments.push_back(f);
  }
  return b;
}

std::shared_ptr<const v1::RunEvent> breakup_event(std::int64_t run, std::uint64_t seq,
                                                  const BreakupReport& b) {
  auto e = std::make_shared<v1::RunEvent>();
  e->set_run_id(run);
  e->set_seq(seq);
  *e->mutable_breakup() = to_proto(b);
  return e;
}

std::shared_ptr<const v1::RunEvent> progress_event(std::int64_t run, std::uint64_t seq,
                                                   std::uint64_t fragments) {
  auto e = std::make_shared<v1::RunEvent>();
  e->set_run_id(run);
  e->set_seq(seq);
  e->mutable_progress()->set_sim_time_s(10.0 * static_cast<double>(seq));
  e->mutable_progress()->set_objects_alive(100 + fragments);
  e->mutable_progress()->mutable_objects_by_type()->set_payload(100);
  e->mutable_progress()->mutable_objects_by_type()->set_fragments(fragments);
  return e;
}

TEST(BreakupStore, KeepsBreakupsAndTheirFragmentsOnceAndListsThemInPages) {
  TempDir dir;
  Store store(dir.path() + "/k.db");
  const std::int64_t id = store.create_run(v1::Scenario(), 1, 0.0);
  const BreakupReport first = explosion_report(1, 25544, kFirstFragmentId, 30);
  const BreakupReport second = explosion_report(2, 43013, kFirstFragmentId + 30, 5);
  store.append_event(progress_event(id, 1, 0));
  store.append_breakup(breakup_event(id, 2, first), fragments_of(first));
  store.append_event(progress_event(id, 3, 30));
  // A resumed run re-emits the breakup with the same number: nothing is stored twice.
  store.append_breakup(breakup_event(id, 2, first), fragments_of(first));
  store.append_breakup(breakup_event(id, 4, second), fragments_of(second));
  store.flush();

  auto events = store.read_events(id, 0, 100);
  ASSERT_EQ(events.size(), 4u);
  ASSERT_TRUE(events[1].has_breakup());
  EXPECT_EQ(events[1].breakup().breakup_id(), 1u);
  EXPECT_EQ(events[1].breakup().kind(), v1::BREAKUP_KIND_EXPLOSION);
  EXPECT_EQ(events[1].breakup().parents_size(), 1);
  EXPECT_EQ(events[1].breakup().parents(0), 25544u);
  EXPECT_EQ(events[1].breakup().fragment_count(), 30u);
  EXPECT_EQ(store.read_events(id, 0, 100, true).size(), 2u);  // without progress: the breakups

  v1::ListFragmentsRequest request;
  request.set_run_id(id);
  request.set_page_size(20);
  auto page = store.list_fragments(request);
  EXPECT_EQ(page.total, 35u);
  ASSERT_EQ(page.items.size(), 20u);
  EXPECT_EQ(page.items.front().id(), kFirstFragmentId);
  EXPECT_EQ(page.items.front().parent_id(), 25544u);
  EXPECT_DOUBLE_EQ(page.items[3].mass_kg(), 3.5);
  EXPECT_DOUBLE_EQ(page.items[3].delta_v_m_s(), 13.0);
  EXPECT_DOUBLE_EQ(page.items[3].characteristic_length_m(), 0.13);
  ASSERT_FALSE(page.next_token.empty());
  request.set_page_token(page.next_token);
  page = store.list_fragments(request);
  ASSERT_EQ(page.items.size(), 15u);
  EXPECT_TRUE(page.next_token.empty());
  EXPECT_EQ(page.items.back().id(), kFirstFragmentId + 34);
  EXPECT_EQ(page.items.back().breakup_id(), 2u);

  request.clear_page_token();
  request.set_breakup_id(2);
  page = store.list_fragments(request);
  ASSERT_EQ(page.items.size(), 5u);
  EXPECT_EQ(page.items.front().id(), kFirstFragmentId + 30);
  EXPECT_EQ(page.items.front().parent_id(), 43013u);

  for (const char* bad : {"-5", "abc", "12x"}) {
    request.set_page_token(bad);
    EXPECT_THROW(store.list_fragments(request), std::invalid_argument) << bad;
  }

  v1::GetRunStatsRequest stats_request;
  stats_request.set_run_id(id);
  v1::RunStats stats = store.run_stats(stats_request, 100.0);
  EXPECT_EQ(stats.breakups(), 2u);
  EXPECT_EQ(stats.fragments(), 35u);
  ASSERT_EQ(stats.objects_alive_size(), 2);
  EXPECT_EQ(stats.objects_alive(1).by_type().fragments(), 30u);
  EXPECT_EQ(stats.objects_alive(1).by_type().payload(), 100u);

  EXPECT_TRUE(store.delete_run(id));
  request.clear_page_token();
  request.clear_breakup_id();
  EXPECT_EQ(store.list_fragments(request).total, 0u);
  EXPECT_EQ(store.run_stats(stats_request, 100.0).breakups(), 0u);
}

TEST(BreakupStore, ConjunctionListingsNameFragments) {
  TempDir dir;
  Store store(dir.path() + "/k.db");
  const std::int64_t id = store.create_run(v1::Scenario(), 1, 0.0);
  store.set_object_names(id, {{5, "TIROS 1"}});
  auto e = std::make_shared<v1::RunEvent>();
  e->set_run_id(id);
  e->set_seq(1);
  e->mutable_encounter()->set_id1(5);
  e->mutable_encounter()->set_id2(kFirstFragmentId + 7);
  store.append_event(e);
  store.flush();
  v1::ListConjunctionsRequest request;
  request.set_run_id(id);
  auto page = store.list_conjunctions(request);
  ASSERT_EQ(page.items.size(), 1u);
  EXPECT_EQ(page.items[0].name1(), "TIROS 1");
  EXPECT_EQ(page.items[0].name2(), "FRAGMENT " + std::to_string(kFirstFragmentId + 7));
}

// The schema of version 2, as a daemon before breakups left it.
const char* const kSchemaV2 = R"sql(
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
  INSERT INTO runs(name, state, scenario, threads, created_unix_s) VALUES('old', 3, X'', 1, 5.0);
  PRAGMA user_version = 2;
)sql";

TEST(BreakupStore, MigratesADatabaseOfTheVersionBefore) {
  TempDir dir;
  const std::string path = dir.path() + "/old.db";
  {
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
    char* message = nullptr;
    ASSERT_EQ(sqlite3_exec(db, kSchemaV2, nullptr, nullptr, &message), SQLITE_OK) << (message ? message : "");
    sqlite3_close(db);
  }
  Store store(path);
  EXPECT_GE(Store::kSchemaVersion, 3);
  EXPECT_EQ(store.schema_version(), Store::kSchemaVersion);
  auto run = store.get_run(1);
  ASSERT_TRUE(run);
  EXPECT_EQ(run->name(), "old");
  const BreakupReport b = explosion_report(1, 7, kFirstFragmentId, 3);
  store.append_breakup(breakup_event(1, 1, b), fragments_of(b));
  store.flush();
  v1::ListFragmentsRequest request;
  request.set_run_id(1);
  EXPECT_EQ(store.list_fragments(request).items.size(), 3u);
}

TEST(BreakupRelay, HandsBreakupsToStoreAndHubInSequence) {
  TempDir dir;
  Store store(dir.path() + "/k.db");
  const std::int64_t id = store.create_run(v1::Scenario(), 1, 0.0);
  EventHub hub;
  {
    EventRelay relay(id, hub, store, std::chrono::milliseconds(1));
    BurnUp burn_up;
    burn_up.id = 9;
    relay.on_burn_up(1, burn_up);
    relay.on_breakup(2, explosion_report(1, 25544, kFirstFragmentId, 12));
    Progress progress;
    progress.objects_alive = 111;
    progress.objects_by_type.fragments = 12;
    relay.on_progress(3, progress);
    relay.on_breakup(4, explosion_report(2, 43013, kFirstFragmentId + 12, 4));
    relay.drain();
  }
  store.flush();
  auto read = hub.read_after(0, 100);
  ASSERT_EQ(read.events.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(read.events[i]->seq(), i + 1);
  EXPECT_TRUE(read.events[0]->has_burn_up());
  ASSERT_TRUE(read.events[1]->has_breakup());
  EXPECT_EQ(read.events[1]->breakup().first_id(), kFirstFragmentId);
  EXPECT_EQ(read.events[1]->breakup().last_id(), kFirstFragmentId + 11);
  EXPECT_EQ(read.events[2]->progress().objects_by_type().fragments(), 12u);
  EXPECT_EQ(read.events[3]->breakup().breakup_id(), 2u);

  auto stored = store.read_events(id, 0, 100);
  ASSERT_EQ(stored.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i)
    EXPECT_EQ(stored[i].SerializeAsString(), read.events[i]->SerializeAsString());
  v1::ListFragmentsRequest request;
  request.set_run_id(id);
  auto page = store.list_fragments(request);
  ASSERT_EQ(page.items.size(), 16u);
  EXPECT_EQ(page.items[12].breakup_id(), 2u);
  EXPECT_EQ(page.items[12].parent_id(), 43013u);
}

}  // namespace
}  // namespace kessler::server
