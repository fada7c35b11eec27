// The store's ensembles on their own: an ensemble and its member runs in one go, listing and paging,
// counts by state, what the aggregates read of a member (progress samples by time, collision and
// conjunction times by kappa, catastrophic collision breakups), and members deleted one by one.
#include <gtest/gtest.h>

#include <memory>

#include "server/store.hpp"
#include "tests/service/temp_dir.hpp"

namespace kessler::server {
namespace {

std::shared_ptr<const v1::RunEvent> encounter(std::int64_t run, std::uint64_t seq, double tca_s, double kappa,
                                              v1::EncounterKind kind) {
  auto e = std::make_shared<v1::RunEvent>();
  e->set_run_id(run);
  e->set_seq(seq);
  auto* c = e->mutable_encounter();
  c->set_id1(1);
  c->set_id2(2 + seq);
  c->set_tca_s(tca_s);
  c->set_kappa(kappa);
  c->set_kind(kind);
  return e;
}

std::shared_ptr<const v1::RunEvent> progress(std::int64_t run, std::uint64_t seq, double t,
                                             std::uint64_t alive) {
  auto e = std::make_shared<v1::RunEvent>();
  e->set_run_id(run);
  e->set_seq(seq);
  e->mutable_progress()->set_sim_time_s(t);
  e->mutable_progress()->set_objects_alive(alive);
  e->mutable_progress()->mutable_objects_by_type()->set_debris(alive);
  return e;
}

std::shared_ptr<const v1::RunEvent> breakup(std::int64_t run, std::uint64_t seq, std::uint32_t id, double t,
                                            bool catastrophic, v1::BreakupSource source) {
  auto e = std::make_shared<v1::RunEvent>();
  e->set_run_id(run);
  e->set_seq(seq);
  auto* b = e->mutable_breakup();
  b->set_breakup_id(id);
  b->set_time_s(t);
  b->set_catastrophic(catastrophic);
  b->set_source(source);
  b->set_kind(v1::BREAKUP_KIND_COLLISION);
  return e;
}

TEST(EnsembleStore, CreatesTheMembersAndListsThem) {
  TempDir dir;
  Store store(dir.path() + "/k.db");
  EXPECT_EQ(store.schema_version(), Store::kSchemaVersion);
  v1::Scenario submitted;
  submitted.set_name("mc");
  submitted.mutable_ensemble()->set_members(3);
  std::vector<v1::Scenario> members(3);
  for (std::size_t k = 0; k < 3; ++k) {
    members[k].set_name("mc");
    members[k].set_seed(7 + k);
  }
  const std::int64_t standalone = store.create_run(v1::Scenario(), 1, 1.0);
  auto [id, runs] = store.create_ensemble(submitted, members, 2, 7, 100.0);
  ASSERT_EQ(runs.size(), 3u);
  auto second = store.create_ensemble(submitted, {members[0]}, 1, 7, 200.0);

  auto e = store.get_ensemble(id);
  ASSERT_TRUE(e);
  EXPECT_EQ(e->name, "mc");
  EXPECT_EQ(e->members, 3u);
  EXPECT_EQ(e->base_seed, 7u);
  EXPECT_EQ(e->created_unix_s, 100.0);
  EXPECT_EQ(e->scenario.ensemble().members(), 3u);
  EXPECT_FALSE(store.get_ensemble(999));
  EXPECT_EQ(store.get_run(standalone)->ensemble_id(), 0);

  auto listed = store.ensemble_runs(id);
  ASSERT_EQ(listed.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(listed[k].id(), runs[k]);
    EXPECT_EQ(listed[k].ensemble_id(), id);
    EXPECT_EQ(listed[k].member_index(), k);
    EXPECT_EQ(listed[k].threads(), 2);
    EXPECT_EQ(store.get_run(runs[k])->scenario().seed(), 7 + k);
  }
  store.set_finished(runs[0], v1::RUN_STATE_SUCCEEDED, 110.0, "", nullptr);
  store.set_running(runs[1], 105.0);
  auto counts = store.ensemble_states(id);
  EXPECT_EQ(counts[v1::RUN_STATE_SUCCEEDED], 1u);
  EXPECT_EQ(counts[v1::RUN_STATE_RUNNING], 1u);
  EXPECT_EQ(counts[v1::RUN_STATE_QUEUED], 1u);

  auto page = store.list_ensembles(1, "");
  ASSERT_EQ(page.items.size(), 1u);
  EXPECT_EQ(page.items[0].id, second.first);  // newest first
  auto rest = store.list_ensembles(1, page.next_token);
  ASSERT_EQ(rest.items.size(), 1u);
  EXPECT_EQ(rest.items[0].id, id);
  EXPECT_TRUE(rest.next_token.empty());
  EXPECT_THROW(store.list_ensembles(1, "x"), std::invalid_argument);

  EXPECT_TRUE(store.delete_run(runs[2]));  // a member goes; the ensemble stays
  EXPECT_EQ(store.ensemble_runs(id).size(), 2u);
  EXPECT_TRUE(store.get_ensemble(id));
}

TEST(EnsembleStore, ReadsAMembersResults) {
  TempDir dir;
  Store store(dir.path() + "/k.db");
  const std::int64_t run = store.create_run(v1::Scenario(), 1, 1.0);
  store.append_event(progress(run, 1, 0, 100));
  store.append_event(encounter(run, 2, 5, 3.0, v1::ENCOUNTER_KIND_CONJUNCTION));
  store.append_event(encounter(run, 3, 8, 0.5, v1::ENCOUNTER_KIND_COLLISION));
  store.append_event(encounter(run, 4, 9, 0.2, v1::ENCOUNTER_KIND_EVASION));  // not counted
  store.append_event(progress(run, 5, 10, 99));
  store.append_breakup(breakup(run, 6, 1, 8, true, v1::BREAKUP_SOURCE_COLLISION), {});
  store.append_breakup(breakup(run, 7, 2, 9, true, v1::BREAKUP_SOURCE_SCHEDULED), {});  // not a collision
  store.append_event(encounter(run, 8, 1, 1.0, v1::ENCOUNTER_KIND_CONJUNCTION));
  store.append_event(progress(run, 9, 10, 98));  // the same time: replaces the one before
  store.flush();
  MemberResults r = store.member_results(run, {1.0, 5.0});
  ASSERT_EQ(r.alive.size(), 2u);
  EXPECT_EQ(r.alive[0].objects_alive(), 100u);
  EXPECT_EQ(r.alive[1].sim_time_s(), 10.0);
  EXPECT_EQ(r.alive[1].objects_alive(), 98u);
  EXPECT_EQ(r.alive[1].by_type().debris(), 98u);
  EXPECT_EQ(r.collision_times, (std::vector<double>{8}));
  EXPECT_EQ(r.catastrophic_times, (std::vector<double>{8}));
  ASSERT_EQ(r.conjunction_times.size(), 2u);
  EXPECT_EQ(r.conjunction_times[0], (std::vector<double>{1, 8}));
  EXPECT_EQ(r.conjunction_times[1], (std::vector<double>{1, 5, 8}));
}

}  // namespace
}  // namespace kessler::server
