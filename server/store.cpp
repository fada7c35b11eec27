// The store's database: the schema and its migrations, the connections. Runs are in store_runs.cpp,
// the writer thread in store_writer.cpp, the queries in store_queries.cpp, breakups in
// store_breakups.cpp, ensembles in store_ensembles.cpp.
#include "server/store.hpp"

#include <pthread.h>
#include <sys/statvfs.h>

#include <filesystem>

#include "server/store_internal.hpp"

namespace kessler::server {

using namespace detail;

bool is_terminal(v1::RunState state) {
  return state == v1::RUN_STATE_SUCCEEDED || state == v1::RUN_STATE_FAILED ||
         state == v1::RUN_STATE_CANCELLED;
}

namespace {

// Schema migrations, in order: migration i brings the schema from version i to i + 1. Never edit one
// that has shipped; append a new one.
const char* const kMigrations[] = {
    R"sql(
    CREATE TABLE runs (
      id INTEGER PRIMARY KEY AUTOINCREMENT,
      name TEXT NOT NULL,
      state INTEGER NOT NULL,
      scenario BLOB NOT NULL,
      threads INTEGER NOT NULL,
      created_unix_s REAL NOT NULL,
      started_unix_s REAL NOT NULL DEFAULT 0,
      finished_unix_s REAL NOT NULL DEFAULT 0,
      error TEXT NOT NULL DEFAULT '',
      summary BLOB
    );
    CREATE INDEX runs_by_state ON runs(state, id);
    -- Every event, its payload the RunEvent message. Encounters (kind 2) also carry the columns the
    -- conjunction queries filter on, so one row per event serves both the stream and the queries.
    CREATE TABLE events (
      run_id INTEGER NOT NULL,
      seq INTEGER NOT NULL,
      kind INTEGER NOT NULL,
      payload BLOB NOT NULL,
      id1 INTEGER,
      id2 INTEGER,
      tca_s REAL,
      miss_distance_m REAL,
      kappa REAL,
      encounter_kind INTEGER,
      PRIMARY KEY (run_id, seq)
    ) WITHOUT ROWID;
    CREATE INDEX encounters_by_pair ON events(run_id, id1, id2, miss_distance_m) WHERE kind = 2;
    CREATE TABLE checkpoints (
      run_id INTEGER PRIMARY KEY,
      last_seq INTEGER NOT NULL,
      step INTEGER NOT NULL,
      bytes BLOB NOT NULL
    );
    )sql",
    // The ingest report of a run's catalog, and its objects' names for the conjunction listings.
    R"sql(
    ALTER TABLE runs ADD COLUMN ingest BLOB;
    CREATE TABLE object_names (
      run_id INTEGER NOT NULL,
      object_id INTEGER NOT NULL,
      name TEXT NOT NULL,
      PRIMARY KEY (run_id, object_id)
    ) WITHOUT ROWID;
    )sql",
    // Breakups (their events are kind 4) and the fragments they made.
    R"sql(
    CREATE TABLE breakups (
      run_id INTEGER NOT NULL,
      breakup_id INTEGER NOT NULL,
      seq INTEGER NOT NULL,
      time_s REAL NOT NULL,
      kind INTEGER NOT NULL,
      source INTEGER NOT NULL,
      catastrophic INTEGER NOT NULL,
      fragment_count INTEGER NOT NULL,
      first_id INTEGER NOT NULL,
      last_id INTEGER NOT NULL,
      remnant_id INTEGER NOT NULL,
      PRIMARY KEY (run_id, breakup_id)
    ) WITHOUT ROWID;
    CREATE TABLE fragments (
      run_id INTEGER NOT NULL,
      fragment_id INTEGER NOT NULL,
      breakup_id INTEGER NOT NULL,
      parent_id INTEGER NOT NULL,
      characteristic_length_m REAL NOT NULL,
      area_to_mass_m2_kg REAL NOT NULL,
      mass_kg REAL NOT NULL,
      delta_v_m_s REAL NOT NULL,
      PRIMARY KEY (run_id, fragment_id)
    ) WITHOUT ROWID;
    CREATE INDEX fragments_by_breakup ON fragments(run_id, breakup_id, fragment_id);
    )sql",
    // Lifecycle events of runs with traffic (their events are kind 5): launches, ends of life, disposals.
    R"sql(
    CREATE TABLE lifecycle_events (
      run_id INTEGER NOT NULL,
      seq INTEGER NOT NULL,
      kind INTEGER NOT NULL,
      time_s REAL NOT NULL,
      first_id INTEGER NOT NULL,
      last_id INTEGER NOT NULL,
      plan_row INTEGER NOT NULL,
      altitude_m REAL NOT NULL,
      PRIMARY KEY (run_id, seq)
    ) WITHOUT ROWID;
    )sql",
    // Monte Carlo ensembles: the submitted scenario, and each member run's ensemble and index.
    R"sql(
    CREATE TABLE ensembles (
      id INTEGER PRIMARY KEY AUTOINCREMENT,
      name TEXT NOT NULL,
      scenario BLOB NOT NULL,
      members INTEGER NOT NULL,
      base_seed INTEGER NOT NULL,
      created_unix_s REAL NOT NULL
    );
    ALTER TABLE runs ADD COLUMN ensemble_id INTEGER NOT NULL DEFAULT 0;
    ALTER TABLE runs ADD COLUMN member_index INTEGER NOT NULL DEFAULT 0;
    CREATE INDEX runs_by_ensemble ON runs(ensemble_id, member_index) WHERE ensemble_id != 0;
    )sql",
    // Who submitted each run and ensemble (a token's name; '' without tokens), and the client's request
    // id of a submission, so a retry finds the first run.
    R"sql(
    ALTER TABLE runs ADD COLUMN submitter TEXT NOT NULL DEFAULT '';
    ALTER TABLE runs ADD COLUMN request_id TEXT;
    CREATE UNIQUE INDEX runs_by_request ON runs(submitter, request_id) WHERE request_id IS NOT NULL;
    CREATE INDEX runs_by_submitter ON runs(submitter, state);
    ALTER TABLE ensembles ADD COLUMN submitter TEXT NOT NULL DEFAULT '';
    ALTER TABLE ensembles ADD COLUMN request_id TEXT;
    CREATE UNIQUE INDEX ensembles_by_request ON ensembles(submitter, request_id) WHERE request_id IS NOT NULL;
    )sql",
    // Population snapshots: one compressed blob per run and step (server/snapshot_codec.hpp).
    R"sql(
    CREATE TABLE snapshots (
      run_id INTEGER NOT NULL,
      step INTEGER NOT NULL,
      sim_time_s REAL NOT NULL,
      objects INTEGER NOT NULL,
      bytes BLOB NOT NULL,
      PRIMARY KEY (run_id, step)
    ) WITHOUT ROWID;
    )sql",
};
constexpr int kMigrationCount = sizeof(kMigrations) / sizeof(kMigrations[0]);
static_assert(kMigrationCount == Store::kSchemaVersion);

// Bytes an unprivileged writer may still use on the filesystem holding `path` (max when unknown).
std::uint64_t free_bytes_at(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::absolute(path).parent_path();
  struct statvfs fs {};
  if (::statvfs(parent.c_str(), &fs) != 0) return UINT64_MAX;
  return static_cast<std::uint64_t>(fs.f_bavail) * fs.f_frsize;
}

}  // namespace

Store::Store(const std::string& path, std::chrono::milliseconds min_checkpoint_interval)
    : path_(path), min_checkpoint_interval_(min_checkpoint_interval) {
  prepare_private_files(path);
  writer_db_ = open_connection(path);
  all_.push_back(writer_db_);
  // Migrations run on the writer's connection before the writer thread starts.
  int version = 0;
  {
    Statement s(writer_db_, "PRAGMA user_version");
    if (s.step()) version = static_cast<int>(s.i64(0));
  }
  if (version > kSchemaVersion)
    throw StoreError("store: " + path + " has schema version " + std::to_string(version) +
                     ", newer than this kesslerd (" + std::to_string(kSchemaVersion) + ")");
  for (int v = version; v < kSchemaVersion; ++v) {
    exec(writer_db_, "BEGIN IMMEDIATE");
    try {
      exec(writer_db_, kMigrations[v]);
      exec(writer_db_, "PRAGMA user_version = " + std::to_string(v + 1));
      exec(writer_db_, "COMMIT");
    } catch (...) {
      sqlite3_exec(writer_db_, "ROLLBACK", nullptr, nullptr, nullptr);
      throw;
    }
  }
  check_at_open();
  writer_ = std::thread([this] {
    pthread_setname_np(pthread_self(), "kessler-store");  // for top -H and profilers
    writer_loop();
  });
}

Store::~Store() {
  {
    std::lock_guard lock(queue_mutex_);
    stopping_ = true;
  }
  queue_cv_.notify_all();
  if (writer_.joinable()) writer_.join();
  for (sqlite3* db : all_) sqlite3_close(db);
}

// Refuses a damaged database, quarantines runs whose stored events disagree with their summaries, and
// drops the checkpoints of succeeded runs (nothing resumes them). A store that cannot write (a full
// disk) still opens, for reads.
void Store::check_at_open() {
  DatabaseCheck check = check_database(writer_db_);
  if (!check.structure_error.empty()) {
    std::string runs;
    for (const auto& [id, why] : check.corrupt_runs) runs += (runs.empty() ? "" : ", ") + std::to_string(id);
    throw StoreError(
        "store: " + path_ + " is damaged (" + check.structure_error + ")" +
        (runs.empty() ? "" : "; runs whose stored events disagree with their summaries: " + runs) +
        "; restore it from a backup, or recover it with sqlite3's .recover into a new file");
  }
  quarantined_ = std::move(check.corrupt_runs);
  try {
    exec(writer_db_, "DELETE FROM checkpoints WHERE run_id IN (SELECT id FROM runs WHERE state = " +
                         std::to_string(static_cast<int>(v1::RUN_STATE_SUCCEEDED)) + ")");
  } catch (const StoreError& e) {
    health_.record_failure(e.what());
  }
}

bool Store::probe_writable() {
  try {
    throw_if_failing_for_test();
    Lease lease(*this);
    exec(lease.db(), "BEGIN IMMEDIATE");
    try {
      // Grows the database by a few pages and frees them: needs the space a small batch of events needs.
      exec(lease.db(),
           "INSERT INTO checkpoints(run_id, last_seq, step, bytes) VALUES(-1, 0, 0, zeroblob(65536)); "
           "DELETE FROM checkpoints WHERE run_id = -1");
      exec(lease.db(), "COMMIT");
    } catch (...) {
      sqlite3_exec(lease.db(), "ROLLBACK", nullptr, nullptr, nullptr);
      throw;
    }
    const std::uint64_t free_bytes = free_bytes_at(path_);
    if (free_bytes < min_free_bytes_)
      throw StoreError("store: " + std::to_string(free_bytes >> 20) +
                       " MB free on the database's filesystem, below the " +
                       std::to_string(min_free_bytes_ >> 20) + " MB writes resume at");
    health_.record_success();
    return true;
  } catch (const StoreError& e) {
    health_.record_failure(e.what());
    return false;
  }
}

void Store::set_write_failure_handler(std::function<void(std::int64_t, const std::string&)> handler) {
  std::lock_guard lock(handler_mutex_);
  write_failure_handler_ = std::move(handler);
}

void Store::fail_writes_for_test(const std::string& error) {
  std::lock_guard lock(test_fault_mutex_);
  test_fault_ = error;
}

void Store::throw_if_failing_for_test() {
  std::lock_guard lock(test_fault_mutex_);
  if (!test_fault_.empty()) throw StoreError("store: " + test_fault_);
}

sqlite3* Store::acquire() {
  std::lock_guard lock(pool_mutex_);
  if (!pool_.empty()) {
    sqlite3* db = pool_.back();
    pool_.pop_back();
    return db;
  }
  sqlite3* db = open_connection(path_);
  all_.push_back(db);
  return db;
}

void Store::release(sqlite3* db) {
  std::lock_guard lock(pool_mutex_);
  pool_.push_back(db);
}

int Store::schema_version() {
  Lease lease(*this);
  Statement s(lease.db(), "PRAGMA user_version");
  return s.step() ? static_cast<int>(s.i64(0)) : 0;
}

}  // namespace kessler::server
