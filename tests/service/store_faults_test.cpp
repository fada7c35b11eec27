// The store under faults: a full disk (a small tmpfs this test mounts, or an injected failure where it
// cannot mount), a table gone, damaged files; and what it keeps private and prunes.
#include <gtest/gtest.h>
#include <sqlite3.h>
#include <sys/mount.h>
#include <sys/stat.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <random>
#include <set>
#include <thread>

#include "server/store.hpp"
#include "tests/service/temp_dir.hpp"

namespace kessler::server {
namespace {

std::shared_ptr<const v1::RunEvent> encounter(std::int64_t run, std::uint64_t seq, std::size_t padding = 0,
                                              v1::EncounterKind kind = v1::ENCOUNTER_KIND_CONJUNCTION) {
  auto e = std::make_shared<v1::RunEvent>();
  e->set_run_id(run);
  e->set_seq(seq);
  auto* c = e->mutable_encounter();
  c->set_id1(seq);
  c->set_id2(seq + 1);
  c->set_tca_s(static_cast<double>(seq));
  c->set_miss_distance_m(100.0);
  c->set_kappa(1.0);
  c->set_kind(kind);
  c->set_seq(seq);
  if (padding > 0) c->set_name1(std::string(padding, 'x'));  // bulk, to fill a disk
  return e;
}

// Runs the write-failure handler records, with their errors.
struct FailureLog {
  std::mutex mutex;
  std::map<std::int64_t, std::string> runs;
  void attach(Store& store) {
    store.set_write_failure_handler([this](std::int64_t id, const std::string& error) {
      std::lock_guard lock(mutex);
      runs[id] = error;
    });
  }
  std::map<std::int64_t, std::string> seen() {
    std::lock_guard lock(mutex);
    return runs;
  }
};

// A succeeded run of `n` encounters (every fifth a collision) with a summary that counts them.
std::int64_t succeeded_run(Store& store, std::uint64_t n) {
  const std::int64_t id = store.create_run(v1::Scenario(), 1, 1.0);
  for (std::uint64_t s = 1; s <= n; ++s)
    store.append_event(
        encounter(id, s, 0, s % 5 == 0 ? v1::ENCOUNTER_KIND_COLLISION : v1::ENCOUNTER_KIND_CONJUNCTION));
  store.flush();
  v1::RunSummary summary;
  summary.set_events(n);
  summary.set_conjunctions(n);
  summary.set_collisions(n / 5);
  store.set_finished(id, v1::RUN_STATE_SUCCEEDED, 2.0, "", &summary);
  return id;
}

std::uint64_t stored_total(Store& store, std::int64_t run_id) {
  v1::ListConjunctionsRequest request;
  request.set_run_id(run_id);
  request.set_page_size(1);
  return store.list_conjunctions(request).total;
}

TEST(StoreFaults, AnInjectedWriteFailureFailsTheRunsInTheBatchAndTheStoreRecovers) {
  TempDir dir;
  Store store(dir.path() + "/k.db");
  FailureLog failures;
  failures.attach(store);
  const std::int64_t before = succeeded_run(store, 40);
  const std::int64_t victim = store.create_run(v1::Scenario(), 1, 3.0);
  store.fail_writes_for_test("database or disk is full");
  for (std::uint64_t s = 1; s <= 10; ++s) store.append_event(encounter(victim, s));
  store.flush();  // returns: the failed batch counts as done
  EXPECT_FALSE(store.health().writable());
  EXPECT_NE(store.health().error().find("disk is full"), std::string::npos);
  ASSERT_EQ(failures.seen().count(victim), 1u);
  EXPECT_EQ(failures.seen().count(before), 0u);
  EXPECT_FALSE(store.probe_writable());
  // Reads go on; what was written before is intact.
  EXPECT_EQ(stored_total(store, before), 40u);
  EXPECT_EQ(store.max_seq(victim), 0u);
  // Space returns: a probe passes; the failed run gets nothing more written (it fails), others do.
  store.fail_writes_for_test("");
  EXPECT_TRUE(store.probe_writable());
  EXPECT_TRUE(store.health().writable());
  store.append_event(encounter(victim, 11));
  const std::int64_t after = store.create_run(v1::Scenario(), 1, 4.0);
  for (std::uint64_t s = 1; s <= 5; ++s) store.append_event(encounter(after, s));
  store.flush();
  EXPECT_EQ(store.max_seq(victim), 0u);
  EXPECT_EQ(store.max_seq(after), 5u);
}

// Mounts a tmpfs of `size_mb` at `path` for the test's life (root only; false where it cannot).
class SmallFilesystem {
 public:
  SmallFilesystem(const std::string& path, int size_mb) : path_(path) {
    const std::string options = "size=" + std::to_string(size_mb) + "m,mode=0700";
    mounted_ = ::mount("tmpfs", path.c_str(), "tmpfs", 0, options.c_str()) == 0;
  }
  ~SmallFilesystem() {
    if (mounted_) ::umount2(path_.c_str(), MNT_DETACH);
  }
  bool mounted() const { return mounted_; }

 private:
  std::string path_;
  bool mounted_ = false;
};

TEST(StoreFaults, AFullDiskFailsTheWritingRunKeepsReadsAndEarlierRunsAndRecoversWhenSpaceReturns) {
  TempDir dir;
  const std::string mount_point = dir.path() + "/small";
  std::filesystem::create_directory(mount_point);
  SmallFilesystem fs(mount_point, 8);
  if (!fs.mounted())
    GTEST_SKIP() << "cannot mount a tmpfs here (not root); the injected failure test covers it";
  const std::string filler = mount_point + "/filler";
  Store store(mount_point + "/k.db");
  store.set_min_free_bytes(2 << 20);
  FailureLog failures;
  failures.attach(store);
  const std::int64_t before = succeeded_run(store, 200);
  // Take the rest of the disk but a little, then write a run's bulky events until the disk is full.
  {
    std::ofstream out(filler, std::ios::binary);
    const std::string block(1 << 16, '\0');
    while (out.write(block.data(), static_cast<std::streamsize>(block.size())) && out.flush()) {
    }
  }
  std::filesystem::resize_file(filler, std::filesystem::file_size(filler) - (1 << 20));
  const std::int64_t victim = store.create_run(v1::Scenario(), 1, 3.0);
  for (std::uint64_t s = 1; s <= 400 && failures.seen().empty(); ++s) {
    store.append_event(encounter(victim, s, 16 << 10));
    if (s % 20 == 0) store.flush();
  }
  store.flush();
  ASSERT_EQ(failures.seen().count(victim), 1u) << "the disk never filled";
  EXPECT_NE(failures.seen()[victim].find("full"), std::string::npos) << failures.seen()[victim];
  EXPECT_FALSE(store.health().writable());
  EXPECT_FALSE(store.probe_writable());
  EXPECT_EQ(stored_total(store, before), 200u);
  EXPECT_TRUE(store.get_run(before).has_value());
  // Space returns.
  std::filesystem::remove(filler);
  EXPECT_TRUE(store.probe_writable());
  const std::int64_t after = store.create_run(v1::Scenario(), 1, 4.0);
  for (std::uint64_t s = 1; s <= 50; ++s) store.append_event(encounter(after, s));
  store.flush();
  EXPECT_EQ(store.max_seq(after), 50u);
  EXPECT_EQ(stored_total(store, before), 200u);
}

TEST(StoreFaults, ATableDroppedUnderTheDaemonFailsTheWritingRunWithoutEndingIt) {
  TempDir dir;
  const std::string path = dir.path() + "/k.db";
  Store store(path);
  FailureLog failures;
  failures.attach(store);
  const std::int64_t run = store.create_run(v1::Scenario(), 1, 1.0);
  store.append_event(encounter(run, 1));
  store.flush();
  sqlite3* other = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &other), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(other, "DROP TABLE events", nullptr, nullptr, nullptr), SQLITE_OK);
  sqlite3_close(other);
  store.append_event(encounter(run, 2));
  store.flush();
  ASSERT_EQ(failures.seen().count(run), 1u);
  EXPECT_NE(failures.seen()[run].find("events"), std::string::npos) << failures.seen()[run];
  EXPECT_FALSE(store.health().writable());
}

TEST(StoreFaults, AMissingTableIsRefusedAtOpenNamingIt) {
  TempDir dir;
  const std::string path = dir.path() + "/k.db";
  { Store store(path); }
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(db, "DROP TABLE lifecycle_events", nullptr, nullptr, nullptr), SQLITE_OK);
  sqlite3_close(db);
  try {
    Store store(path);
    FAIL() << "a database without its lifecycle_events table was opened";
  } catch (const StoreError& e) {
    EXPECT_NE(std::string(e.what()).find("lifecycle_events is missing"), std::string::npos) << e.what();
  }
}

TEST(StoreFaults, RunsWhoseStoredEventsDisagreeWithTheirSummaryAreQuarantinedByName) {
  TempDir dir;
  const std::string path = dir.path() + "/k.db";
  std::int64_t intact = 0, damaged = 0;
  {
    Store store(path);
    intact = succeeded_run(store, 100);
    damaged = succeeded_run(store, 100);
  }
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  const std::string lose = "DELETE FROM events WHERE run_id = " + std::to_string(damaged) + " AND seq > 37";
  ASSERT_EQ(sqlite3_exec(db, lose.c_str(), nullptr, nullptr, nullptr), SQLITE_OK);
  sqlite3_close(db);
  Store store(path);
  ASSERT_EQ(store.quarantined_runs().size(), 1u);
  ASSERT_EQ(store.quarantined_runs().count(damaged), 1u);
  EXPECT_EQ(store.quarantined_runs().at(damaged), "37 encounters stored, its summary says 100");
  EXPECT_EQ(stored_total(store, intact), 100u);
}

// Flips random bits in copies of a database (past its first page, whose damage SQLite refuses by
// itself): 100 flips in half the copies, 10 in the others. The store either refuses a copy (its
// structure is damaged) or opens it, and then every run it does not quarantine has exactly its
// summary's totals, or a read of it fails. Serving a wrong total silently is the one outcome not allowed.
TEST(StoreFaults, BitFlipsNeverServeWrongTotals) {
  TempDir dir;
  const std::string original = dir.path() + "/original.db";
  std::vector<std::int64_t> runs;
  {
    Store store(original);
    for (int r = 0; r < 4; ++r) runs.push_back(succeeded_run(store, 3000));
  }
  const auto size = std::filesystem::file_size(original);
  int refused = 0, quarantined = 0, failed_reads = 0, intact = 0;
  for (unsigned seed = 1; seed <= 16; ++seed) {
    const std::string copy = dir.path() + "/copy" + std::to_string(seed) + ".db";
    std::filesystem::copy_file(original, copy);
    {
      std::fstream f(copy, std::ios::in | std::ios::out | std::ios::binary);
      std::mt19937_64 rng(seed);
      const int flips = seed <= 8 ? 100 : 10;
      for (int i = 0; i < flips; ++i) {
        const auto at = static_cast<std::streamoff>(4096 + rng() % (size - 4096));
        char c = 0;
        f.seekg(at);
        f.get(c);
        c = static_cast<char>(c ^ (1 << (rng() % 8)));
        f.seekp(at);
        f.put(c);
      }
    }
    try {
      Store store(copy);
      quarantined += static_cast<int>(store.quarantined_runs().size());
      for (std::int64_t id : runs) {
        if (store.quarantined_runs().count(id)) continue;
        try {
          auto run = store.get_run(id, false);
          if (!run) continue;  // a damaged runs row reads as no run: nothing served
          EXPECT_EQ(stored_total(store, id), 3000u) << "seed " << seed << ", run " << id;
          ++intact;
        } catch (const StoreError&) {
          ++failed_reads;  // a read SQLite finds malformed is an error, not a wrong answer
        }
      }
    } catch (const StoreError& e) {
      ++refused;
    } catch (const std::exception& e) {
      ADD_FAILURE() << "seed " << seed << ": " << e.what();
    }
  }
  EXPECT_GT(refused + quarantined, 0);
  std::printf("bit flips: %d copies refused, %d runs quarantined, %d reads failed, %d runs served intact\n",
              refused, quarantined, failed_reads, intact);
}

TEST(StoreFaults, TheDatabaseItsWalAndItsFolderArePrivate) {
  TempDir dir;
  const std::string folder = dir.path() + "/var/kessler";
  const std::string path = folder + "/k.db";
  Store store(path);
  store.create_run(v1::Scenario(), 1, 1.0);
  store.flush();
  auto mode = [](const std::string& p) {
    struct stat st {};
    EXPECT_EQ(::stat(p.c_str(), &st), 0) << p;
    return st.st_mode & 0777;
  };
  EXPECT_EQ(mode(folder), 0700u);
  EXPECT_EQ(mode(path), 0600u);
  EXPECT_EQ(mode(path + "-wal"), 0600u);
}

TEST(StoreFaults, AnExistingWorldReadableDatabaseIsMadePrivateAtOpen) {
  TempDir dir;
  const std::string path = dir.path() + "/k.db";
  { Store store(path); }
  ::chmod(path.c_str(), 0644);
  Store store(path);
  struct stat st {};
  ASSERT_EQ(::stat(path.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0600u);
}

TEST(StoreFaults, ASucceededRunsCheckpointIsPrunedAFailedOrCancelledRunKeepsItsLast) {
  TempDir dir;
  Store store(dir.path() + "/k.db");
  std::map<v1::RunState, std::int64_t> runs;
  for (v1::RunState state : {v1::RUN_STATE_SUCCEEDED, v1::RUN_STATE_FAILED, v1::RUN_STATE_CANCELLED}) {
    const std::int64_t id = store.create_run(v1::Scenario(), 1, 1.0);
    store.append_event(encounter(id, 1));
    store.append_checkpoint(id, 1, 5, std::string("state"));
    store.flush();
    ASSERT_TRUE(store.latest_checkpoint(id));
    store.set_finished(id, state, 2.0, "", nullptr);
    runs[state] = id;
  }
  EXPECT_FALSE(store.latest_checkpoint(runs[v1::RUN_STATE_SUCCEEDED]));
  EXPECT_TRUE(store.latest_checkpoint(runs[v1::RUN_STATE_FAILED]));
  EXPECT_TRUE(store.latest_checkpoint(runs[v1::RUN_STATE_CANCELLED]));
}

}  // namespace
}  // namespace kessler::server
