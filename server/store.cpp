#include "server/store.hpp"

#include <sqlite3.h>

#include <pthread.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <stdexcept>

namespace kessler::server {

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
};
constexpr int kMigrationCount = sizeof(kMigrations) / sizeof(kMigrations[0]);
static_assert(kMigrationCount == Store::kSchemaVersion);

enum EventKind : int { kKindProgress = 1, kKindEncounter = 2, kKindBurnUp = 3 };

double thread_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

void check(int rc, sqlite3* db, const char* what) {
  if (rc != SQLITE_OK && rc != SQLITE_DONE && rc != SQLITE_ROW)
    throw StoreError(std::string("store: ") + what + ": " + (db ? sqlite3_errmsg(db) : sqlite3_errstr(rc)));
}

void exec(sqlite3* db, const std::string& sql) {
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

sqlite3* open_connection(const std::string& path) {
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

}  // namespace

struct Store::Pending {
  std::shared_ptr<const v1::RunEvent> event;  // or a checkpoint:
  std::int64_t run_id = 0;
  std::uint64_t last_seq = 0;
  std::int64_t step = 0;
  std::shared_ptr<const std::string> checkpoint;
  bool is_checkpoint = false;
  bool discard = false;  // a checkpoint item that drops the run's waiting checkpoint
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

Store::Store(const std::string& path, std::chrono::milliseconds min_checkpoint_interval)
    : path_(path), min_checkpoint_interval_(min_checkpoint_interval) {
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

// ---- runs ----

std::int64_t Store::create_run(const v1::Scenario& scenario, int threads, double created_unix_s) {
  Lease lease(*this);
  Statement s(lease.db(),
              "INSERT INTO runs(name, state, scenario, threads, created_unix_s) VALUES(?, ?, ?, ?, ?)");
  std::string bytes = scenario.SerializeAsString();
  s.bind(1, scenario.name()).bind(2, static_cast<int>(v1::RUN_STATE_QUEUED)).bind_blob(3, bytes);
  s.bind(4, threads).bind(5, created_unix_s);
  s.run();
  return sqlite3_last_insert_rowid(lease.db());
}

namespace {

const char* const kRunColumns =
    "id, name, state, threads, created_unix_s, started_unix_s, finished_unix_s, error, summary";

v1::Run run_from_row(const Statement& s) {
  v1::Run run;
  run.set_id(s.i64(0));
  run.set_name(s.text(1));
  run.set_state(static_cast<v1::RunState>(s.i64(2)));
  run.set_threads(static_cast<int>(s.i64(3)));
  run.set_created_unix_s(s.f64(4));
  run.set_started_unix_s(s.f64(5));
  run.set_finished_unix_s(s.f64(6));
  run.set_error(s.text(7));
  if (!s.is_null(8)) run.mutable_summary()->ParseFromString(s.text(8));
  return run;
}

}  // namespace

std::optional<v1::Run> Store::get_run(std::int64_t run_id, bool with_scenario) {
  Lease lease(*this);
  Statement s(lease.db(), std::string("SELECT ") + kRunColumns + ", scenario FROM runs WHERE id = ?");
  s.bind(1, run_id);
  if (!s.step()) return std::nullopt;
  v1::Run run = run_from_row(s);
  if (with_scenario) run.mutable_scenario()->ParseFromString(s.text(9));
  Statement last(lease.db(), "SELECT MAX(seq) FROM events WHERE run_id = ?");
  last.bind(1, run_id);
  if (last.step() && !last.is_null(0)) run.set_last_seq(static_cast<std::uint64_t>(last.i64(0)));
  Statement progress(lease.db(),
                     "SELECT payload FROM events WHERE run_id = ? AND kind = ? ORDER BY seq DESC LIMIT 1");
  progress.bind(1, run_id).bind(2, static_cast<int>(kKindProgress));
  if (progress.step()) {
    v1::RunEvent event;
    if (event.ParseFromString(progress.text(0))) *run.mutable_progress() = event.progress();
  }
  return run;
}

Page<v1::Run> Store::list_runs(const std::vector<v1::RunState>& states, int page_size,
                               const std::string& page_token) {
  page_size = page_size <= 0 ? 50 : std::min(page_size, 1000);
  std::int64_t before = INT64_MAX;
  if (!page_token.empty()) {
    try {
      before = std::stoll(page_token);
    } catch (...) {
      throw std::invalid_argument("page_token: not a token from a previous page");
    }
  }
  std::string sql = std::string("SELECT ") + kRunColumns + " FROM runs WHERE id < ?";
  if (!states.empty()) {
    sql += " AND state IN (";
    for (std::size_t i = 0; i < states.size(); ++i) sql += (i ? ",?" : "?");
    sql += ")";
  }
  sql += " ORDER BY id DESC LIMIT ?";
  Lease lease(*this);
  Statement s(lease.db(), sql);
  int i = 1;
  s.bind(i++, before);
  for (auto state : states) s.bind(i++, static_cast<int>(state));
  s.bind(i++, page_size + 1);
  Page<v1::Run> page;
  while (s.step()) page.items.push_back(run_from_row(s));
  if (static_cast<int>(page.items.size()) > page_size) {
    page.items.pop_back();
    page.next_token = std::to_string(page.items.back().id());
  }
  return page;
}

std::vector<std::int64_t> Store::runs_in_state(v1::RunState state) {
  Lease lease(*this);
  Statement s(lease.db(), "SELECT id FROM runs WHERE state = ? ORDER BY id");
  s.bind(1, static_cast<int>(state));
  std::vector<std::int64_t> ids;
  while (s.step()) ids.push_back(s.i64(0));
  return ids;
}

void Store::set_running(std::int64_t run_id, double started_unix_s) {
  Lease lease(*this);
  Statement s(lease.db(), "UPDATE runs SET state = ?, started_unix_s = ? WHERE id = ?");
  s.bind(1, static_cast<int>(v1::RUN_STATE_RUNNING)).bind(2, started_unix_s).bind(3, run_id);
  s.run();
}

void Store::set_queued(std::int64_t run_id) {
  Lease lease(*this);
  Statement s(lease.db(), "UPDATE runs SET state = ? WHERE id = ?");
  s.bind(1, static_cast<int>(v1::RUN_STATE_QUEUED)).bind(2, run_id);
  s.run();
}

void Store::set_finished(std::int64_t run_id, v1::RunState state, double finished_unix_s,
                         const std::string& error, const v1::RunSummary* summary) {
  Lease lease(*this);
  Statement s(lease.db(),
              "UPDATE runs SET state = ?, finished_unix_s = ?, error = ?, summary = ? WHERE id = ?");
  s.bind(1, static_cast<int>(state)).bind(2, finished_unix_s).bind(3, error);
  std::string bytes = summary ? summary->SerializeAsString() : std::string();
  if (summary) s.bind_blob(4, bytes);
  s.bind(5, run_id);
  s.run();
}

bool Store::delete_run(std::int64_t run_id) {
  flush();
  Lease lease(*this);
  exec(lease.db(), "BEGIN IMMEDIATE");
  try {
    bool existed = false;
    for (const char* sql : {"DELETE FROM events WHERE run_id = ?", "DELETE FROM checkpoints WHERE run_id = ?",
                            "DELETE FROM runs WHERE id = ?"}) {
      Statement s(lease.db(), sql);
      s.bind(1, run_id);
      s.run();
      existed = sqlite3_changes(lease.db()) > 0;
    }
    exec(lease.db(), "COMMIT");
    return existed;
  } catch (...) {
    sqlite3_exec(lease.db(), "ROLLBACK", nullptr, nullptr, nullptr);
    throw;
  }
}

// ---- the writer ----

void Store::append_event(std::shared_ptr<const v1::RunEvent> event) {
  Pending p;
  p.event = std::move(event);
  {
    std::lock_guard lock(queue_mutex_);
    queue_.push_back(std::move(p));
    ++appended_;
  }
  queue_cv_.notify_one();
}

void Store::append_events(const std::vector<std::shared_ptr<const v1::RunEvent>>& events) {
  if (events.empty()) return;
  {
    std::lock_guard lock(queue_mutex_);
    for (const auto& e : events) {
      Pending p;
      p.event = e;
      queue_.push_back(std::move(p));
    }
    appended_ += events.size();
  }
  queue_cv_.notify_one();
}

void Store::append_checkpoint(std::int64_t run_id, std::uint64_t last_seq, std::int64_t step,
                              std::string bytes) {
  append_checkpoint(run_id, last_seq, step, std::make_shared<const std::string>(std::move(bytes)));
}

void Store::discard_waiting_checkpoint(std::int64_t run_id) {
  Pending p;
  p.is_checkpoint = true;
  p.discard = true;
  p.run_id = run_id;
  {
    std::lock_guard lock(queue_mutex_);
    queue_.push_back(std::move(p));
    ++appended_;
  }
  queue_cv_.notify_one();
}

void Store::append_checkpoint(std::int64_t run_id, std::uint64_t last_seq, std::int64_t step,
                              std::shared_ptr<const std::string> bytes) {
  Pending p;
  p.is_checkpoint = true;
  p.run_id = run_id;
  p.last_seq = last_seq;
  p.step = step;
  p.checkpoint = std::move(bytes);
  {
    std::lock_guard lock(queue_mutex_);
    queue_.push_back(std::move(p));
    ++appended_;
  }
  queue_cv_.notify_one();
}

void Store::flush() {
  std::unique_lock lock(queue_mutex_);
  std::uint64_t target = appended_;
  ++flush_waiters_;  // a held checkpoint is written now
  queue_cv_.notify_one();
  flushed_cv_.wait(lock, [&] { return committed_ >= target; });
  --flush_waiters_;
}

// The writer's prepared statements, made once for its connection.
struct Store::WriterStatements {
  explicit WriterStatements(sqlite3* db)
      : event_insert(db,
                     "INSERT OR IGNORE INTO events(run_id, seq, kind, payload, id1, id2, tca_s, "
                     "miss_distance_m, kappa, encounter_kind) VALUES(?, ?, ?, ?, ?, ?, ?, ?, ?, ?)"),
        checkpoint_upsert(db,
                          "INSERT INTO checkpoints(run_id, last_seq, step, bytes) VALUES(?, ?, ?, ?) "
                          "ON CONFLICT(run_id) DO UPDATE SET last_seq = excluded.last_seq, "
                          "step = excluded.step, bytes = excluded.bytes WHERE excluded.step >= "
                          "checkpoints.step") {}
  Statement event_insert;
  Statement checkpoint_upsert;
};

void Store::writer_loop() {
  using Clock = std::chrono::steady_clock;
  WriterStatements statements(writer_db_);
  std::vector<Pending> batch, to_write;
  // The newest checkpoint of each run not yet written, and when each run's last one was written. A
  // checkpoint waits until min_checkpoint_interval has passed since its run's last write (or a flush,
  // or the end); a newer one arriving meanwhile replaces it, unwritten: only the latest per run is
  // kept anyway, and a run resumed from an older one re-emits the same events.
  std::map<std::int64_t, Pending> held;
  std::map<std::int64_t, Clock::time_point> last_written;
  auto due_at = [&](std::int64_t run_id) {
    auto it = last_written.find(run_id);
    return it == last_written.end() ? Clock::time_point::min() : it->second + min_checkpoint_interval_;
  };
  for (;;) {
    bool force = false;
    {
      std::unique_lock lock(queue_mutex_);
      auto ready = [&] { return stopping_ || !queue_.empty() || (!held.empty() && flush_waiters_ > 0); };
      if (held.empty()) {
        queue_cv_.wait(lock, ready);
      } else {
        auto next = Clock::time_point::max();
        for (const auto& [run_id, p] : held) next = std::min(next, due_at(run_id));
        queue_cv_.wait_until(lock, next, ready);
      }
      if (queue_.empty() && held.empty() && stopping_) return;
      force = stopping_ || flush_waiters_ > 0;
      // Up to 20,000 items per transaction: large enough to amortise the commit, small enough to
      // keep the lag behind the simulation short.
      std::size_t n = std::min<std::size_t>(queue_.size(), 20000);
      batch.clear();
      batch.reserve(n);
      for (std::size_t i = 0; i < n; ++i) {
        batch.push_back(std::move(queue_.front()));
        queue_.pop_front();
      }
      // Every item taken now is in the store's view of the queue: a flush waiting for it also
      // waits for the checkpoints it holds.
      if (queue_.empty() && flush_waiters_ > 0) force = true;
    }
    const double cpu0 = thread_cpu_s();
    std::uint64_t done = 0;  // items committed or superseded by this pass
    to_write.clear();
    for (Pending& p : batch) {
      if (!p.is_checkpoint) {
        to_write.push_back(std::move(p));
        continue;
      }
      auto it = held.find(p.run_id);
      if (p.discard) {
        if (it != held.end()) {
          held.erase(it);
          ++done;  // the dropped checkpoint
        }
        ++done;  // this item
        continue;
      }
      if (it == held.end()) {
        held.emplace(p.run_id, std::move(p));
      } else {
        if (p.step >= it->second.step) std::swap(it->second, p);
        ++done;  // the older of the two is never written
      }
    }
    const auto now = Clock::now();
    for (auto it = held.begin(); it != held.end();) {
      if (force || now >= due_at(it->first)) {
        last_written[it->first] = now;
        to_write.push_back(std::move(it->second));  // after the events before it
        it = held.erase(it);
      } else {
        ++it;
      }
    }
    if (!to_write.empty()) write_batch(to_write, statements);
    done += to_write.size();
    const double cpu = thread_cpu_s() - cpu0;
    {
      std::lock_guard lock(queue_mutex_);
      committed_ += done;
      writer_cpu_s_ += cpu;
    }
    flushed_cv_.notify_all();
  }
}

void Store::write_batch(std::vector<Pending>& batch, WriterStatements& statements) {
  sqlite3* db = writer_db_;
  exec(db, "BEGIN IMMEDIATE");
  Statement& event_insert = statements.event_insert;
  Statement& checkpoint_upsert = statements.checkpoint_upsert;
  std::string payload;
  std::uint64_t written = 0;
  for (Pending& p : batch) {
    if (p.is_checkpoint) {
      checkpoint_upsert.bind(1, p.run_id).bind(2, p.last_seq).bind(3, p.step).bind_blob(4, *p.checkpoint);
      checkpoint_upsert.run();
      continue;
    }
    const v1::RunEvent& e = *p.event;
    int kind = e.has_progress() ? kKindProgress : e.has_encounter() ? kKindEncounter : kKindBurnUp;
    payload.clear();
    e.SerializeToString(&payload);
    event_insert.bind(1, e.run_id()).bind(2, e.seq()).bind(3, kind).bind_blob(4, payload);
    if (e.has_encounter()) {
      const v1::Encounter& c = e.encounter();
      event_insert.bind(5, c.id1()).bind(6, c.id2()).bind(7, c.tca_s()).bind(8, c.miss_distance_m());
      event_insert.bind(9, c.kappa()).bind(10, static_cast<int>(c.kind()));
    } else {
      event_insert.bind_null(5).bind_null(6).bind_null(7).bind_null(8).bind_null(9).bind_null(10);
    }
    event_insert.run();
    ++written;
  }
  exec(db, "COMMIT");
  std::lock_guard lock(queue_mutex_);
  events_written_ += written;
}

double Store::writer_cpu_s() const {
  std::lock_guard lock(const_cast<std::mutex&>(queue_mutex_));
  return writer_cpu_s_;
}

std::uint64_t Store::events_written() const {
  std::lock_guard lock(const_cast<std::mutex&>(queue_mutex_));
  return events_written_;
}

// ---- reads ----

std::uint64_t Store::max_seq(std::int64_t run_id) {
  Lease lease(*this);
  Statement s(lease.db(), "SELECT MAX(seq) FROM events WHERE run_id = ?");
  s.bind(1, run_id);
  return s.step() && !s.is_null(0) ? static_cast<std::uint64_t>(s.i64(0)) : 0;
}

std::vector<v1::RunEvent> Store::read_events(std::int64_t run_id, std::uint64_t after_seq, int limit,
                                             bool no_progress) {
  Lease lease(*this);
  Statement s(lease.db(),
              no_progress ? "SELECT payload FROM events WHERE run_id = ? AND seq > ? AND kind != 1 "
                            "ORDER BY seq LIMIT ?"
                          : "SELECT payload FROM events WHERE run_id = ? AND seq > ? ORDER BY seq LIMIT ?");
  s.bind(1, run_id).bind(2, after_seq).bind(3, limit);
  std::vector<v1::RunEvent> events;
  while (s.step()) {
    events.emplace_back();
    if (!events.back().ParseFromString(s.text(0))) throw StoreError("store: corrupt event payload");
  }
  return events;
}

std::optional<StoredCheckpoint> Store::latest_checkpoint(std::int64_t run_id) {
  Lease lease(*this);
  Statement s(lease.db(), "SELECT last_seq, step, bytes FROM checkpoints WHERE run_id = ?");
  s.bind(1, run_id);
  if (!s.step()) return std::nullopt;
  return StoredCheckpoint{static_cast<std::uint64_t>(s.i64(0)), s.i64(1), s.text(2)};
}

Page<v1::Encounter> Store::list_conjunctions(const v1::ListConjunctionsRequest& r) {
  int page_size = r.page_size() <= 0 ? 1000 : std::min(r.page_size(), 100000);
  std::int64_t offset = 0;
  if (!r.page_token().empty()) {
    try {
      offset = std::stoll(r.page_token());
    } catch (...) {
      throw std::invalid_argument("page_token: not a token from a previous page");
    }
  }
  std::string where = "c.run_id = ?1 AND c.kind = 2";
  if (r.has_kappa_min()) where += " AND c.kappa >= ?2";
  if (r.has_kappa_max()) where += " AND c.kappa <= ?3";
  if (r.has_object_id()) where += " AND (c.id1 = ?4 OR c.id2 = ?4)";
  if (r.has_time_min_s()) where += " AND c.tca_s >= ?5";
  if (r.has_time_max_s()) where += " AND c.tca_s <= ?6";
  if (r.collisions_only())
    where += " AND c.encounter_kind = 1";
  else if (!r.include_evasions())
    where += " AND c.encounter_kind != 2";
  // The closest encounter of each pair: SQLite takes the other columns of a MIN() aggregate from the
  // row holding the minimum.
  std::string selection = r.closest_per_pair()
                              ? "SELECT c.seq, c.payload, MIN(c.miss_distance_m) FROM events c WHERE " +
                                    where + " GROUP BY c.id1, c.id2"
                              : "SELECT c.seq, c.payload FROM events c WHERE " + where;
  auto bind_all = [&](Statement& s) {
    s.bind(1, r.run_id());
    if (r.has_kappa_min()) s.bind(2, r.kappa_min());
    if (r.has_kappa_max()) s.bind(3, r.kappa_max());
    if (r.has_object_id()) s.bind(4, r.object_id());
    if (r.has_time_min_s()) s.bind(5, r.time_min_s());
    if (r.has_time_max_s()) s.bind(6, r.time_max_s());
  };
  Lease lease(*this);
  Page<v1::Encounter> page;
  {
    Statement count(lease.db(), "SELECT COUNT(*) FROM (" + selection + ")");
    bind_all(count);
    if (count.step()) page.total = static_cast<std::uint64_t>(count.i64(0));
  }
  Statement s(lease.db(), "SELECT seq, payload FROM (" + selection + ") ORDER BY seq LIMIT ?7 OFFSET ?8");
  bind_all(s);
  s.bind(7, page_size + 1).bind(8, offset);
  while (s.step()) {
    v1::RunEvent event;
    if (!event.ParseFromString(s.text(1))) throw StoreError("store: corrupt event payload");
    v1::Encounter encounter = event.encounter();
    encounter.set_seq(static_cast<std::uint64_t>(s.i64(0)));
    page.items.push_back(std::move(encounter));
  }
  if (static_cast<int>(page.items.size()) > page_size) {
    page.items.pop_back();
    page.next_token = std::to_string(offset + page_size);
  }
  return page;
}

v1::RunStats Store::run_stats(const v1::GetRunStatsRequest& request, double run_length_s) {
  v1::RunStats stats;
  stats.set_run_id(request.run_id());
  double bin = request.time_bin_s() > 0 ? request.time_bin_s() : std::max(run_length_s, 1.0) / 24.0;
  stats.set_time_bin_s(bin);
  std::size_t bins = static_cast<std::size_t>(std::max(1.0, std::ceil(run_length_s / bin)));
  for (std::size_t i = 0; i < bins; ++i) stats.add_bin_start_s(static_cast<double>(i) * bin);
  std::vector<double> kappas(request.kappas().begin(), request.kappas().end());
  if (kappas.empty()) kappas = {1.0, 2.0, 5.0, 10.0};
  std::sort(kappas.begin(), kappas.end());

  Lease lease(*this);
  {
    Statement counts(lease.db(),
                     "SELECT encounter_kind, COUNT(*) FROM events WHERE run_id = ? AND kind = 2 GROUP BY 1");
    counts.bind(1, request.run_id());
    while (counts.step()) {
      auto n = static_cast<std::uint64_t>(counts.i64(1));
      switch (counts.i64(0)) {
        case 0:
          stats.set_conjunctions(stats.conjunctions() + n);
          break;
        case 1:
          stats.set_collisions(n);
          stats.set_conjunctions(stats.conjunctions() + n);
          break;
        case 2:
          stats.set_evasions(n);
          break;
      }
    }
    Statement burn_ups(lease.db(), "SELECT COUNT(*) FROM events WHERE run_id = ? AND kind = 3");
    burn_ups.bind(1, request.run_id());
    if (burn_ups.step()) stats.set_burn_ups(static_cast<std::uint64_t>(burn_ups.i64(0)));
  }
  for (double kappa : kappas) {
    v1::KappaSeries* series = stats.add_by_kappa();
    series->set_kappa(kappa);
    std::vector<std::uint64_t> per_bin(bins, 0);
    Statement s(lease.db(),
                "SELECT CAST(tca_s / ? AS INTEGER), COUNT(*) FROM events WHERE run_id = ? AND kind = 2 "
                "AND encounter_kind != 2 AND kappa <= ? GROUP BY 1");
    s.bind(1, bin).bind(2, request.run_id()).bind(3, kappa);
    while (s.step()) {
      std::int64_t b = std::clamp<std::int64_t>(s.i64(0), 0, static_cast<std::int64_t>(bins) - 1);
      per_bin[static_cast<std::size_t>(b)] += static_cast<std::uint64_t>(s.i64(1));
    }
    std::uint64_t total = 0;
    for (std::uint64_t n : per_bin) {
      total += n;
      series->add_per_bin(n);
      series->add_cumulative(total);
    }
  }
  Statement alive(lease.db(), "SELECT payload FROM events WHERE run_id = ? AND kind = 1 ORDER BY seq");
  alive.bind(1, request.run_id());
  while (alive.step()) {
    v1::RunEvent event;
    if (!event.ParseFromString(alive.text(0))) continue;
    v1::AliveSample* sample = stats.add_objects_alive();
    sample->set_sim_time_s(event.progress().sim_time_s());
    sample->set_objects_alive(event.progress().objects_alive());
  }
  return stats;
}

}  // namespace kessler::server
