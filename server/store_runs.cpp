// The store's runs: creation, state changes, listing, deletion, and what is known of a run's population
// (its ingest report and its objects' names).
#include <algorithm>
#include <stdexcept>

#include "server/store.hpp"
#include "server/store_internal.hpp"

namespace kessler::server {

using namespace detail;

// ---- runs ----

std::int64_t Store::create_run(const v1::Scenario& scenario, int threads, double created_unix_s,
                               const std::string& submitter, const std::string& request_id) {
  throw_if_failing_for_test();
  Lease lease(*this);
  return insert_run(lease.db(), scenario, threads, created_unix_s, 0, 0, submitter, request_id);
}

namespace {

std::optional<std::int64_t> id_of_request(sqlite3* db, const char* table, const std::string& submitter,
                                          const std::string& request_id) {
  Statement s(db, std::string("SELECT id FROM ") + table + " WHERE submitter = ? AND request_id = ?");
  s.bind(1, submitter).bind(2, request_id);
  if (!s.step()) return std::nullopt;
  return s.i64(0);
}

std::optional<std::string> submitter_of(sqlite3* db, const char* table, std::int64_t id) {
  Statement s(db, std::string("SELECT submitter FROM ") + table + " WHERE id = ?");
  s.bind(1, id);
  if (!s.step()) return std::nullopt;
  return s.text(0);
}

}  // namespace

std::optional<std::int64_t> Store::run_of_request(const std::string& submitter,
                                                  const std::string& request_id) {
  Lease lease(*this);
  return id_of_request(lease.db(), "runs", submitter, request_id);
}

std::optional<std::int64_t> Store::ensemble_of_request(const std::string& submitter,
                                                       const std::string& request_id) {
  Lease lease(*this);
  return id_of_request(lease.db(), "ensembles", submitter, request_id);
}

std::optional<std::string> Store::run_submitter(std::int64_t run_id) {
  Lease lease(*this);
  return submitter_of(lease.db(), "runs", run_id);
}

std::optional<std::string> Store::ensemble_submitter(std::int64_t ensemble_id) {
  Lease lease(*this);
  return submitter_of(lease.db(), "ensembles", ensemble_id);
}

std::uint64_t Store::active_runs_of(const std::string& submitter) {
  Lease lease(*this);
  Statement s(lease.db(), "SELECT COUNT(*) FROM runs WHERE submitter = ? AND state IN (?, ?)");
  s.bind(1, submitter)
      .bind(2, static_cast<int>(v1::RUN_STATE_QUEUED))
      .bind(3, static_cast<int>(v1::RUN_STATE_RUNNING));
  return s.step() ? static_cast<std::uint64_t>(s.i64(0)) : 0;
}

namespace detail {

std::int64_t insert_run(sqlite3* db, const v1::Scenario& scenario, int threads, double created_unix_s,
                        std::int64_t ensemble_id, std::uint64_t member_index, const std::string& submitter,
                        const std::string& request_id) {
  Statement s(db,
              "INSERT INTO runs(name, state, scenario, threads, created_unix_s, ensemble_id, member_index, "
              "submitter, request_id) VALUES(?, ?, ?, ?, ?, ?, ?, ?, ?)");
  std::string bytes = scenario.SerializeAsString();
  s.bind(1, scenario.name()).bind(2, static_cast<int>(v1::RUN_STATE_QUEUED)).bind_blob(3, bytes);
  s.bind(4, threads).bind(5, created_unix_s).bind(6, ensemble_id).bind(7, member_index).bind(8, submitter);
  if (request_id.empty())
    s.bind_null(9);
  else
    s.bind(9, request_id);
  s.run();
  return sqlite3_last_insert_rowid(db);
}

}  // namespace detail

namespace {

const char* const kRunColumns =
    "id, name, state, threads, created_unix_s, started_unix_s, finished_unix_s, error, summary, ingest, "
    "ensemble_id, member_index, submitter";

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
  if (!s.is_null(9)) run.mutable_ingest()->ParseFromString(s.text(9));
  run.set_ensemble_id(s.i64(10));
  run.set_member_index(static_cast<std::uint64_t>(s.i64(11)));
  run.set_submitter(s.text(12));
  return run;
}

}  // namespace

namespace detail {
const char* const kRunColumnsSql = kRunColumns;
v1::Run run_row(const Statement& s) {
  return run_from_row(s);
}
}  // namespace detail

std::optional<v1::Run> Store::get_run(std::int64_t run_id, bool with_scenario) {
  Lease lease(*this);
  Statement s(lease.db(), std::string("SELECT ") + kRunColumns + ", scenario FROM runs WHERE id = ?");
  s.bind(1, run_id);
  if (!s.step()) return std::nullopt;
  v1::Run run = run_from_row(s);
  if (with_scenario) run.mutable_scenario()->ParseFromString(s.text(13));
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
                               const std::string& page_token, const std::string* submitter) {
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
  if (submitter) sql += " AND submitter = ?";
  sql += " ORDER BY id DESC LIMIT ?";
  Lease lease(*this);
  Statement s(lease.db(), sql);
  int i = 1;
  s.bind(i++, before);
  for (auto state : states) s.bind(i++, static_cast<int>(state));
  if (submitter) s.bind(i++, *submitter);
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
  throw_if_failing_for_test();
  Lease lease(*this);
  Statement s(lease.db(), "UPDATE runs SET state = ?, started_unix_s = ? WHERE id = ?");
  s.bind(1, static_cast<int>(v1::RUN_STATE_RUNNING)).bind(2, started_unix_s).bind(3, run_id);
  s.run();
}

void Store::set_queued(std::int64_t run_id) {
  throw_if_failing_for_test();
  Lease lease(*this);
  // A resumed run (ResumeRun) drops the end it had; its events and checkpoint stay.
  Statement s(lease.db(),
              "UPDATE runs SET state = ?, finished_unix_s = 0, error = '', summary = NULL WHERE id = ?");
  s.bind(1, static_cast<int>(v1::RUN_STATE_QUEUED)).bind(2, run_id);
  s.run();
}

void Store::set_finished(std::int64_t run_id, v1::RunState state, double finished_unix_s,
                         const std::string& error, const v1::RunSummary* summary) {
  throw_if_failing_for_test();
  Lease lease(*this);
  exec(lease.db(), "BEGIN IMMEDIATE");
  try {
    Statement s(lease.db(),
                "UPDATE runs SET state = ?, finished_unix_s = ?, error = ?, summary = ? WHERE id = ?");
    s.bind(1, static_cast<int>(state)).bind(2, finished_unix_s).bind(3, error);
    std::string bytes = summary ? summary->SerializeAsString() : std::string();
    if (summary) s.bind_blob(4, bytes);
    s.bind(5, run_id);
    s.run();
    // A succeeded run is never resumed: its checkpoint goes. A failed or cancelled one keeps its last.
    if (state == v1::RUN_STATE_SUCCEEDED) {
      Statement prune(lease.db(), "DELETE FROM checkpoints WHERE run_id = ?");
      prune.bind(1, run_id);
      prune.run();
    }
    exec(lease.db(), "COMMIT");
  } catch (...) {
    sqlite3_exec(lease.db(), "ROLLBACK", nullptr, nullptr, nullptr);
    throw;
  }
}

void Store::set_ingest(std::int64_t run_id, const v1::IngestReport& report) {
  Lease lease(*this);
  Statement s(lease.db(), "UPDATE runs SET ingest = ? WHERE id = ?");
  const std::string bytes = report.SerializeAsString();
  s.bind_blob(1, bytes).bind(2, run_id);
  s.run();
}

void Store::set_object_names(std::int64_t run_id,
                             const std::vector<std::pair<std::uint64_t, std::string>>& names) {
  Lease lease(*this);
  exec(lease.db(), "BEGIN IMMEDIATE");
  try {
    Statement s(lease.db(), "INSERT OR IGNORE INTO object_names(run_id, object_id, name) VALUES(?, ?, ?)");
    for (const auto& [id, name] : names) {
      if (name.empty()) continue;
      s.bind(1, run_id).bind(2, id).bind(3, name);
      s.run();
    }
    exec(lease.db(), "COMMIT");
  } catch (...) {
    sqlite3_exec(lease.db(), "ROLLBACK", nullptr, nullptr, nullptr);
    throw;
  }
}

std::map<std::uint64_t, std::string> Store::object_names(std::int64_t run_id) {
  Lease lease(*this);
  Statement s(lease.db(), "SELECT object_id, name FROM object_names WHERE run_id = ?");
  s.bind(1, run_id);
  std::map<std::uint64_t, std::string> names;
  while (s.step()) names.emplace(static_cast<std::uint64_t>(s.i64(0)), s.text(1));
  return names;
}

bool Store::delete_run(std::int64_t run_id) {
  flush();
  Lease lease(*this);
  exec(lease.db(), "BEGIN IMMEDIATE");
  try {
    bool existed = false;
    for (const char* sql :
         {"DELETE FROM events WHERE run_id = ?", "DELETE FROM checkpoints WHERE run_id = ?",
          "DELETE FROM object_names WHERE run_id = ?", "DELETE FROM breakups WHERE run_id = ?",
          "DELETE FROM fragments WHERE run_id = ?", "DELETE FROM lifecycle_events WHERE run_id = ?",
          "DELETE FROM snapshots WHERE run_id = ?", "DELETE FROM runs WHERE id = ?"}) {
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

}  // namespace kessler::server
