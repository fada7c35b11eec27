// The store's health: whether it can write now (a full disk, a read-only file or an I/O error make it
// refuse writes until they pass again), the startup check of the database, and the private files.
//
// A write that fails does not end the daemon: the writer thread rolls its batch back, the runs whose
// events were in it are reported (they fail with the error), reads go on, and the next write that
// passes (a probe, a submission) clears the state. The startup check refuses a database whose
// structure is damaged (`PRAGMA quick_check`, the tables the schema needs) and quarantines each ended
// run whose stored events disagree with its summary, so no wrong totals are served.
#pragma once

#include <cstdint>
#include <map>
#include <mutex>
#include <string>

struct sqlite3;

namespace kessler::server {

class StoreHealth {
 public:
  void record_failure(const std::string& error);
  void record_success();
  bool writable() const;
  // The last failure while not writable (empty when writable).
  std::string error() const;
  // Failures since the store opened.
  std::uint64_t failures() const;

 private:
  mutable std::mutex mutex_;
  bool writable_ = true;
  std::string error_;
  std::uint64_t failures_ = 0;
};

// What the startup check found.
struct DatabaseCheck {
  std::string structure_error;                       // quick_check's first findings, or a missing table
  std::map<std::int64_t, std::string> corrupt_runs;  // run id -> why its stored data is not trusted
};

// Runs PRAGMA quick_check, looks for the schema's tables, and compares each succeeded run's stored
// events (by kind) with its summary's counts. Reads only.
DatabaseCheck check_database(sqlite3* db);

// Creates the database's folder (0700) and file (0600) when missing, so SQLite's WAL and shared-memory
// files, which take the database's mode, are private too; tightens an existing file readable by others.
void prepare_private_files(const std::string& path);

}  // namespace kessler::server
