// What the store's files share (not part of the store's interface): SQLite helpers, the event kinds of
// the events table, and the store's pending writes and pooled connections.
#pragma once

#include <sqlite3.h>

#include <memory>
#include <string>
#include <vector>

#include "server/store.hpp"

namespace kessler::server::detail {

enum EventKind : int {
  kKindProgress = 1,
  kKindEncounter = 2,
  kKindBurnUp = 3,
  kKindBreakup = 4,
  kKindLifecycle = 5,
};

inline void check(int rc, sqlite3* db, const char* what) {
  if (rc != SQLITE_OK && rc != SQLITE_DONE && rc != SQLITE_ROW)
    throw StoreError(std::string("store: ") + what + ": " + (db ? sqlite3_errmsg(db) : sqlite3_errstr(rc)));
}

inline void exec(sqlite3* db, const std::string& sql) {
  char* message = nullptr;
  int rc = sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &message);
  if (rc != SQLITE_OK) {
    std::string text = message ? message : sqlite3_errstr(rc);
    sqlite3_free(message);
    throw StoreError("store: " + text + " in: " + sql.substr(0, 80));
  }
}

// A prepared statement that finalizes itself.
class Statement {
 public:
  Statement(sqlite3* db, const std::string& sql) : db_(db) {
    check(sqlite3_prepare_v2(db, sql.c_str(), -1, &stmt_, nullptr), db, "prepare");
  }
  ~Statement() { sqlite3_finalize(stmt_); }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  Statement& bind(int i, std::int64_t v) { return ok(sqlite3_bind_int64(stmt_, i, v)); }
  Statement& bind(int i, std::uint64_t v) {
    return ok(sqlite3_bind_int64(stmt_, i, static_cast<std::int64_t>(v)));
  }
  Statement& bind(int i, int v) { return ok(sqlite3_bind_int64(stmt_, i, v)); }
  Statement& bind(int i, double v) { return ok(sqlite3_bind_double(stmt_, i, v)); }
  Statement& bind(int i, const std::string& v) {
    return ok(sqlite3_bind_text(stmt_, i, v.data(), static_cast<int>(v.size()), SQLITE_TRANSIENT));
  }
  Statement& bind_null(int i) { return ok(sqlite3_bind_null(stmt_, i)); }
  Statement& bind_blob(int i, const std::string& v) {
    return ok(sqlite3_bind_blob(stmt_, i, v.data(), static_cast<int>(v.size()), SQLITE_STATIC));
  }
  // True while there is a row.
  bool step() {
    int rc = sqlite3_step(stmt_);
    check(rc, db_, "step");
    return rc == SQLITE_ROW;
  }
  void run() {
    step();
    sqlite3_reset(stmt_);
  }
  void reset() {
    sqlite3_reset(stmt_);
    sqlite3_clear_bindings(stmt_);
  }
  std::int64_t i64(int col) const { return sqlite3_column_int64(stmt_, col); }
  double f64(int col) const { return sqlite3_column_double(stmt_, col); }
  bool is_null(int col) const { return sqlite3_column_type(stmt_, col) == SQLITE_NULL; }
  std::string text(int col) const {
    auto* p = reinterpret_cast<const char*>(sqlite3_column_blob(stmt_, col));
    return p ? std::string(p, static_cast<std::size_t>(sqlite3_column_bytes(stmt_, col))) : std::string();
  }

 private:
  Statement& ok(int rc) {
    check(rc, db_, "bind");
    return *this;
  }
  sqlite3* db_;
  sqlite3_stmt* stmt_ = nullptr;
};

// The breakup's row and its fragments' rows (store_breakups.cpp), in the writer's transaction.
extern const char* const kBreakupInsertSql;
extern const char* const kFragmentInsertSql;
void write_breakup_rows(Statement& breakup_insert, Statement& fragment_insert, const v1::RunEvent& event,
                        const std::vector<StoredFragment>& fragments);

// A snapshot's row (store_snapshots.cpp), encoded, in the writer's transaction.
extern const char* const kSnapshotInsertSql;
void write_snapshot_row(Statement& snapshot_insert, std::int64_t run_id, const PopulationSnapshot& snapshot);

// A lifecycle event's row (store_breakups.cpp), in the writer's transaction.
extern const char* const kLifecycleInsertSql;
void write_lifecycle_row(Statement& lifecycle_insert, const v1::RunEvent& event);
// The run's lifecycle events counted by kind into the statistics (launches, objects launched, ...).
void count_lifecycle_events(sqlite3* db, std::int64_t run_id, v1::RunStats& stats);
// Runs (store_runs.cpp): a new queued run's row, and the columns a Run is read from (run_row takes a
// statement that selected kRunColumnsSql first).
std::int64_t insert_run(sqlite3* db, const v1::Scenario& scenario, int threads, double created_unix_s,
                        std::int64_t ensemble_id, std::uint64_t member_index, const std::string& submitter,
                        const std::string& request_id);
extern const char* const kRunColumnsSql;
v1::Run run_row(const Statement& s);

inline sqlite3* open_connection(const std::string& path) {
  sqlite3* db = nullptr;
  int rc = sqlite3_open_v2(path.c_str(), &db,
                           SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_NOMUTEX, nullptr);
  if (rc != SQLITE_OK) {
    std::string reason = db ? sqlite3_errmsg(db) : sqlite3_errstr(rc);
    sqlite3_close(db);
    throw StoreError("store: cannot open " + path + ": " + reason);
  }
  sqlite3_busy_timeout(db, 10000);
  exec(db,
       "PRAGMA journal_mode=WAL; PRAGMA synchronous=NORMAL; PRAGMA cache_size=-65536; PRAGMA "
       "temp_store=MEMORY;");
  return db;
}

}  // namespace kessler::server::detail

namespace kessler::server {

struct Store::Pending {
  std::shared_ptr<const v1::RunEvent> event;  // or a checkpoint:
  std::int64_t run_id = 0;
  std::uint64_t last_seq = 0;
  std::int64_t step = 0;
  std::shared_ptr<const std::string> checkpoint;
  std::shared_ptr<const std::vector<StoredFragment>> fragments;  // a breakup event's
  std::shared_ptr<const PopulationSnapshot> snapshot;            // or a snapshot (with run_id)
  bool is_checkpoint = false;
  bool discard = false;  // a checkpoint item that drops the run's waiting checkpoint
  bool resume = false;   // a control item: the run's write failure is forgotten (it resumes)

  // The run the item belongs to, whatever its kind.
  std::int64_t run() const { return event ? event->run_id() : run_id; }
};

class Store::Lease {
 public:
  explicit Lease(Store& store) : store_(store), db_(store.acquire()) {}
  ~Lease() { store_.release(db_); }
  sqlite3* db() const { return db_; }

 private:
  Store& store_;
  sqlite3* db_;
};

}  // namespace kessler::server
