// Population snapshots in the store: the codec keeps every value bit for bit and refuses what is not a
// snapshot; the store keeps one snapshot per (run, step) (a resumed run's second copy is ignored), lists
// them in pages, reads the last at or before a step, removes them with their run, and migrates a
// database of the previous schema.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <random>

#include "core/simulation/breakups.hpp"
#include "server/snapshot_codec.hpp"
#include "server/store.hpp"
#include "tests/service/temp_dir.hpp"

namespace kessler::server {
namespace {

PopulationSnapshot random_snapshot(std::size_t n, std::int64_t step, std::uint64_t seed = 1) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> u(0.0F, 1.0F);
  PopulationSnapshot s;
  s.step = step;
  s.sim_time_s = 10.0 * static_cast<double>(step);
  s.resize(n);
  ObjectId id = 5;
  for (std::size_t i = 0; i < n; ++i) {
    id += 1 + rng() % 50;
    s.id[i] = i + 1 == n ? kFirstFragmentId + 7 : id;  // a large jump at the end
    s.type[i] = static_cast<ObjectType>(rng() % 4);
    s.status[i] = static_cast<ObjectStatus>(rng() % 2);
    s.radius_m[i] = 0.01F + 10.0F * u(rng);
    s.mass_kg[i] = 1000.0F * u(rng);
    s.semi_major_axis_m[i] = 6.7e6F + 1e6F * u(rng);
    s.eccentricity[i] = 0.1F * u(rng);
    s.inclination_rad[i] = 3.0F * u(rng);
    s.raan_rad[i] = 6.0F * u(rng);
    s.argument_of_perigee_rad[i] = 6.0F * u(rng);
    s.mean_anomaly_rad[i] = -0.0F;
  }
  return s;
}

void expect_same(const PopulationSnapshot& a, const PopulationSnapshot& b) {
  EXPECT_EQ(a.step, b.step);
  EXPECT_EQ(a.sim_time_s, b.sim_time_s);
  EXPECT_EQ(a.id, b.id);
  EXPECT_EQ(a.type, b.type);
  EXPECT_EQ(a.status, b.status);
  EXPECT_EQ(a.radius_m, b.radius_m);
  EXPECT_EQ(a.mass_kg, b.mass_kg);
  EXPECT_EQ(a.semi_major_axis_m, b.semi_major_axis_m);
  EXPECT_EQ(a.eccentricity, b.eccentricity);
  EXPECT_EQ(a.inclination_rad, b.inclination_rad);
  EXPECT_EQ(a.raan_rad, b.raan_rad);
  EXPECT_EQ(a.argument_of_perigee_rad, b.argument_of_perigee_rad);
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_TRUE(std::signbit(b.mean_anomaly_rad[i]));  // -0 kept
}

TEST(SnapshotCodec, RoundTripsEveryValueAndRefusesOtherBytes) {
  const PopulationSnapshot s = random_snapshot(5000, 86400);
  const std::string bytes = encode_snapshot(s);
  EXPECT_LT(bytes.size(), 5000u * 42u);  // smaller than the raw columns
  expect_same(s, decode_snapshot(bytes));
  expect_same(random_snapshot(0, 3), decode_snapshot(encode_snapshot(random_snapshot(0, 3))));
  EXPECT_THROW(decode_snapshot("KSNP"), std::runtime_error);
  EXPECT_THROW(decode_snapshot(std::string(64, 'x')), std::runtime_error);
  std::string corrupt = bytes;
  corrupt[corrupt.size() / 2] ^= 0x55;
  EXPECT_THROW(decode_snapshot(corrupt), std::runtime_error);
  EXPECT_THROW(decode_snapshot(bytes.substr(0, bytes.size() - 9)), std::runtime_error);
}

TEST(SnapshotStore, KeepsOnePerStepListsInPagesAndReadsAtOrBefore) {
  TempDir dir;
  Store store(dir.path() + "/k.db");
  v1::Scenario scenario;
  const std::int64_t run = store.create_run(scenario, 1, 0.0);
  for (std::int64_t step : {0, 100, 200, 300})
    store.append_snapshot(run,
                          std::make_shared<const PopulationSnapshot>(random_snapshot(300, step, step + 1)));
  // A resumed run hands step 200 over again (other contents here, to see which copy stays).
  store.append_snapshot(run, std::make_shared<const PopulationSnapshot>(random_snapshot(10, 200, 99)));
  store.flush();
  Page<StoredSnapshotInfo> page = store.list_snapshots(run, 3, "");
  EXPECT_EQ(page.total, 4u);
  ASSERT_EQ(page.items.size(), 3u);
  EXPECT_EQ(page.items[2].step, 200);
  EXPECT_EQ(page.items[2].objects, 300u);
  EXPECT_GT(page.items[2].stored_bytes, 0u);
  EXPECT_EQ(page.items[1].sim_time_s, 1000.0);
  Page<StoredSnapshotInfo> rest = store.list_snapshots(run, 3, page.next_token);
  ASSERT_EQ(rest.items.size(), 1u);
  EXPECT_EQ(rest.items[0].step, 300);
  EXPECT_TRUE(rest.next_token.empty());
  EXPECT_THROW(store.list_snapshots(run, 3, "x"), std::invalid_argument);

  expect_same(random_snapshot(300, 200, 201), *store.read_snapshot(run, 299));
  EXPECT_EQ(store.read_snapshot(run, std::nullopt)->step, 300);
  EXPECT_EQ(store.read_snapshot(run, 0)->step, 0);
  EXPECT_FALSE(store.read_snapshot(run, -1));
  EXPECT_FALSE(store.read_snapshot(run + 1, std::nullopt));

  EXPECT_TRUE(store.delete_run(run));
  EXPECT_EQ(store.list_snapshots(run, 10, "").total, 0u);
}

TEST(SnapshotStore, MigratesADatabaseOfThePreviousSchema) {
  TempDir dir;
  const std::string path = dir.path() + "/k.db";
  std::int64_t run = 0;
  {
    Store store(path);
    run = store.create_run(v1::Scenario(), 1, 0.0);
  }
  {  // back to the schema before snapshots (6): no snapshots table
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
    ASSERT_EQ(sqlite3_exec(db, "DROP TABLE snapshots; PRAGMA user_version = 6;", nullptr, nullptr, nullptr),
              SQLITE_OK);
    sqlite3_close(db);
  }
  Store store(path);
  EXPECT_EQ(store.schema_version(), Store::kSchemaVersion);
  ASSERT_TRUE(store.get_run(run));
  store.append_snapshot(run, std::make_shared<const PopulationSnapshot>(random_snapshot(10, 0)));
  store.flush();
  EXPECT_EQ(store.list_snapshots(run, 10, "").total, 1u);
}

}  // namespace
}  // namespace kessler::server
