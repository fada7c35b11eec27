#include "server/store_health.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <system_error>

#include "server/store_internal.hpp"

namespace kessler::server {

using namespace detail;

void StoreHealth::record_failure(const std::string& error) {
  std::lock_guard lock(mutex_);
  writable_ = false;
  error_ = error;
  ++failures_;
}

void StoreHealth::record_success() {
  std::lock_guard lock(mutex_);
  writable_ = true;
  error_.clear();
}

bool StoreHealth::writable() const {
  std::lock_guard lock(mutex_);
  return writable_;
}

std::string StoreHealth::error() const {
  std::lock_guard lock(mutex_);
  return error_;
}

std::uint64_t StoreHealth::failures() const {
  std::lock_guard lock(mutex_);
  return failures_;
}

namespace {

constexpr const char* kRequiredTables[] = {"runs",     "events",    "checkpoints",      "object_names",
                                           "breakups", "fragments", "lifecycle_events", "ensembles"};

std::string structure_problem(sqlite3* db) {
  std::string findings;
  {
    Statement s(db, "PRAGMA quick_check(5)");
    while (s.step()) {
      const std::string line = s.text(0);
      if (line == "ok") break;
      findings += (findings.empty() ? "" : "; ") + line;
    }
  }
  if (!findings.empty()) return "PRAGMA quick_check: " + findings;
  for (const char* table : kRequiredTables) {
    Statement s(db, "SELECT 1 FROM sqlite_master WHERE type = 'table' AND name = ?");
    s.bind(1, std::string(table));
    if (!s.step()) return std::string("table ") + table + " is missing";
  }
  return {};
}

// Why a succeeded run's stored events disagree with its summary (empty: they agree).
std::string run_problem(sqlite3* db, std::int64_t run_id, const std::string& summary_bytes) {
  v1::RunSummary summary;
  if (!summary.ParseFromString(summary_bytes)) return "its summary cannot be read";
  std::uint64_t encounters = 0, collisions = 0, burn_ups = 0, numbered = 0;
  Statement s(
      db, "SELECT kind, encounter_kind, COUNT(*) FROM events WHERE run_id = ? GROUP BY kind, encounter_kind");
  s.bind(1, run_id);
  while (s.step()) {
    const std::int64_t kind = s.i64(0);
    const auto n = static_cast<std::uint64_t>(s.i64(2));
    if (kind != kKindProgress) numbered += n;
    if (kind == kKindEncounter) {
      encounters += n;
      if (!s.is_null(1) && s.i64(1) == v1::ENCOUNTER_KIND_COLLISION) collisions += n;
    }
    if (kind == kKindBurnUp) burn_ups += n;
  }
  auto differs = [](const char* what, std::uint64_t stored, std::uint64_t expected) {
    return std::to_string(stored) + " " + what + " stored, its summary says " + std::to_string(expected);
  };
  if (encounters != summary.conjunctions() + summary.evasions())
    return differs("encounters", encounters, summary.conjunctions() + summary.evasions());
  if (collisions != summary.collisions()) return differs("collisions", collisions, summary.collisions());
  if (burn_ups != summary.burn_ups()) return differs("burn-ups", burn_ups, summary.burn_ups());
  if (numbered != summary.events()) return differs("events", numbered, summary.events());
  return {};
}

}  // namespace

DatabaseCheck check_database(sqlite3* db) {
  DatabaseCheck out;
  out.structure_error = structure_problem(db);
  if (!out.structure_error.empty() && out.structure_error.rfind("table ", 0) == 0) return out;
  try {
    Statement runs(db, "SELECT id, summary FROM runs WHERE state = ? AND summary IS NOT NULL ORDER BY id");
    runs.bind(1, static_cast<int>(v1::RUN_STATE_SUCCEEDED));
    while (runs.step()) {
      const std::int64_t id = runs.i64(0);
      try {
        std::string why = run_problem(db, id, runs.text(1));
        if (!why.empty()) out.corrupt_runs[id] = why;
      } catch (const StoreError& e) {
        out.corrupt_runs[id] = e.what();
      }
    }
  } catch (const StoreError& e) {
    if (out.structure_error.empty()) out.structure_error = e.what();
  }
  return out;
}

void prepare_private_files(const std::string& path) {
  namespace fs = std::filesystem;
  if (path.empty() || path == ":memory:" || path.rfind("file:", 0) == 0) return;
  const fs::path file(path);
  const fs::path parent = file.parent_path();
  if (!parent.empty() && !fs::exists(parent)) {
    fs::create_directories(parent);
    fs::permissions(parent, fs::perms::owner_all, fs::perm_options::replace);
  }
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
    if (fd >= 0) ::close(fd);
    return;
  }
  for (const std::string& f : {path, path + "-wal", path + "-shm"})
    if (::stat(f.c_str(), &st) == 0 && (st.st_mode & 077) != 0) ::chmod(f.c_str(), st.st_mode & 0700);
}

}  // namespace kessler::server
