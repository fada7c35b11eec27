// The daemon's memory: runs, their events, conjunctions and checkpoints in one SQLite database (WAL).
//
// Writes of events and checkpoints go through one writer thread that batches them into transactions,
// in the order they were handed over, so a checkpoint is stored only after every event before it.
// Events are stored idempotently by (run, sequence number): a resumed run re-emits events after its
// checkpoint with the same numbers and the store keeps the first copy. Reads and the rare run updates
// use their own connections (WAL lets readers run beside the writer).
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "core/simulation/snapshots.hpp"
#include "kessler/v1/names.hpp"
#include "kessler/v1/service.pb.h"
#include "server/store_health.hpp"

struct sqlite3;

namespace kessler::server {

// Thrown for database failures (disk full, read-only file, I/O error, corrupt file).
struct StoreError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct StoredCheckpoint {
  std::uint64_t last_seq = 0;
  std::int64_t step = 0;
  std::string bytes;
};

// One fragment of a breakup as the store keeps it (the breakup's id comes with its event).
struct StoredFragment {
  std::uint64_t id = 0;
  std::uint64_t parent_id = 0;
  double characteristic_length_m = 0.0;
  double area_to_mass_m2_kg = 0.0;
  double mass_kg = 0.0;
  double delta_v_m_s = 0.0;
};

// An ensemble as the store keeps it (its members are runs with its id).
struct StoredEnsemble {
  std::int64_t id = 0;
  std::string name;
  double created_unix_s = 0.0;
  std::uint64_t members = 0;
  std::uint64_t base_seed = 0;
  std::string submitter;
  v1::Scenario scenario;  // as submitted (when asked for)
};

// What the ensemble aggregates take from one member's stored results.
struct MemberResults {
  std::vector<v1::AliveSample> alive;      // its progress events' counts, by time (one per time)
  std::vector<double> collision_times;     // tca_s of its collisions, sorted
  std::vector<double> catastrophic_times;  // time_s of its catastrophic collision breakups, sorted
  std::vector<std::vector<double>> conjunction_times;  // per kappa threshold: tca_s of conjunctions
                                                       // (collisions too, not evasions) at or below it
};

// When a run's launches, re-entries and breakups happened [s since the scenario epoch], in event order.
struct EventTimes {
  std::vector<std::pair<double, std::uint64_t>> launches;  // time, objects launched
  std::vector<double> burn_ups_s;                          // re-entries below the burn-up altitude
  std::vector<double> deorbits_s;                          // disposals that left the run
  std::vector<double> breakups_s;
};

// A stored snapshot's row, without its objects.
struct StoredSnapshotInfo {
  std::int64_t step = 0;
  double sim_time_s = 0.0;
  std::uint64_t objects = 0;
  std::uint64_t stored_bytes = 0;
};

// One page of a query: items and the token of the next page (empty on the last).
template <typename T>
struct Page {
  std::vector<T> items;
  std::string next_token;
  std::uint64_t total = 0;
};

class Store {
 public:
  // Opens (creating when needed) the database at `path` and brings its schema up to date.
  // `min_checkpoint_interval`: a run's checkpoints are written at most this often; one that comes
  // sooner waits (and a newer one replaces it unwritten) until the interval has passed, a flush()
  // or the store's end. 0: each is written as it comes.
  explicit Store(const std::string& path,
                 std::chrono::milliseconds min_checkpoint_interval = std::chrono::milliseconds(0));
  ~Store();
  Store(const Store&) = delete;
  Store& operator=(const Store&) = delete;

  static constexpr int kSchemaVersion = 7;
  int schema_version();

  // Faults (store_health.hpp). Whether writes pass now; a failed write marks the store unwritable
  // until one passes again.
  StoreHealth& health() { return health_; }
  // A small write (grown and committed) and the free space of the database's filesystem (at least
  // min_free_bytes), to learn whether the store can write again. True when it can.
  bool probe_writable();
  // The free space a probe asks for (default 64 MB): after a full disk, a small write may pass in the
  // space a failed batch left in the WAL while the disk is still full.
  void set_min_free_bytes(std::uint64_t bytes) { min_free_bytes_ = bytes; }
  // Called by the writer thread, outside its locks, for each run whose events or checkpoint could not
  // be written (their batch rolled back), with the error.
  void set_write_failure_handler(std::function<void(std::int64_t run_id, const std::string& error)> handler);
  // Runs the startup check quarantined (their stored events disagree with their summaries): id -> why.
  const std::map<std::int64_t, std::string>& quarantined_runs() const { return quarantined_; }
  // Tests where no small filesystem can be mounted: every write fails with `error` (empty: none).
  void fail_writes_for_test(const std::string& error);

  // Runs. The id is assigned here. `submitter`: the token's name ("" without tokens); `request_id`:
  // the client's id of the submission ("" for none), unique per submitter.
  std::int64_t create_run(const v1::Scenario& scenario, int threads, double created_unix_s,
                          const std::string& submitter = "", const std::string& request_id = "");
  // The run a submitter created with this request id, if any.
  std::optional<std::int64_t> run_of_request(const std::string& submitter, const std::string& request_id);
  // The ensemble a submitter created with this request id, if any.
  std::optional<std::int64_t> ensemble_of_request(const std::string& submitter,
                                                  const std::string& request_id);
  // Who submitted the run (nullopt: no such run).
  std::optional<std::string> run_submitter(std::int64_t run_id);
  std::optional<std::string> ensemble_submitter(std::int64_t ensemble_id);
  // The submitter's runs that are queued or running.
  std::uint64_t active_runs_of(const std::string& submitter);
  // nullopt when there is no such run. with_scenario: also decode the stored scenario.
  std::optional<v1::Run> get_run(std::int64_t run_id, bool with_scenario = true);
  // Newest first; page token is the last id of the previous page.
  // `submitter`: only this submitter's runs (nullptr: everyone's).
  Page<v1::Run> list_runs(const std::vector<v1::RunState>& states, int page_size,
                          const std::string& page_token, const std::string* submitter = nullptr);
  // Ids of the runs in a state, oldest first (for recovery at start).
  std::vector<std::int64_t> runs_in_state(v1::RunState state);
  void set_running(std::int64_t run_id, double started_unix_s);
  void set_queued(std::int64_t run_id);
  // A terminal state, with the error or the summary.
  void set_finished(std::int64_t run_id, v1::RunState state, double finished_unix_s, const std::string& error,
                    const v1::RunSummary* summary);
  // What the ingest did with the run's catalog (GetRun's ingest), stored when the population is built.
  void set_ingest(std::int64_t run_id, const v1::IngestReport& report);
  // The names of the run's objects by id, for the conjunction listings; written once per run (a second
  // call keeps the first names). Objects without a name are left out.
  void set_object_names(std::int64_t run_id, const std::vector<std::pair<std::uint64_t, std::string>>& names);
  std::map<std::uint64_t, std::string> object_names(std::int64_t run_id);
  // Removes the run and everything stored for it. False when there was no such run.
  bool delete_run(std::int64_t run_id);

  // Ensembles (store_ensembles.cpp). Creates the ensemble and its member runs (queued, member k from
  // members[k]) in one transaction; returns the ensemble's id and the runs' ids by index.
  std::pair<std::int64_t, std::vector<std::int64_t>> create_ensemble(const v1::Scenario& submitted,
                                                                     const std::vector<v1::Scenario>& members,
                                                                     int threads, std::uint64_t base_seed,
                                                                     double created_unix_s,
                                                                     const std::string& submitter = "",
                                                                     const std::string& request_id = "");
  std::optional<StoredEnsemble> get_ensemble(std::int64_t ensemble_id, bool with_scenario = true);
  // Newest first; the page token is the last id of the previous page.
  // `submitter`: only this submitter's ensembles (nullptr: everyone's).
  Page<StoredEnsemble> list_ensembles(int page_size, const std::string& page_token,
                                      const std::string* submitter = nullptr);
  // The member runs still stored, by index (without their scenarios).
  std::vector<v1::Run> ensemble_runs(std::int64_t ensemble_id);
  // Counts of the member runs by state.
  std::map<v1::RunState, std::uint64_t> ensemble_states(std::int64_t ensemble_id);
  MemberResults member_results(std::int64_t run_id, const std::vector<double>& kappas);

  // Events, through the writer thread. `event` must carry seq and run_id.
  void append_event(std::shared_ptr<const v1::RunEvent> event);
  // A batch, in order: one queue operation for all of it.
  void append_events(const std::vector<std::shared_ptr<const v1::RunEvent>>& events);
  // A breakup event (RunEvent::breakup) with its fragments, in order with the other events; stored
  // idempotently by (run, sequence number) like them.
  void append_breakup(std::shared_ptr<const v1::RunEvent> event, std::vector<StoredFragment> fragments);
  // Stored after every event appended before it (possibly later, see min_checkpoint_interval).
  void append_checkpoint(std::int64_t run_id, std::uint64_t last_seq, std::int64_t step, std::string bytes);
  void append_checkpoint(std::int64_t run_id, std::uint64_t last_seq, std::int64_t step,
                         std::shared_ptr<const std::string> bytes);
  // A run that has ended needs no checkpoint: one still waiting for its interval is dropped unwritten
  // (the stored one stays).
  void discard_waiting_checkpoint(std::int64_t run_id);
  // A run whose writes failed gets nothing more written until this (it is resumed from a checkpoint
  // stored before the failure, ResumeRun); in order with its other items.
  void forget_write_failure(std::int64_t run_id);
  // Blocks until everything appended so far is committed (held checkpoints too, or superseded).
  void flush();
  // The highest sequence number committed for a run (0: none).
  std::uint64_t max_seq(std::int64_t run_id);
  // Committed events with seq > after_seq, in order, at most `limit`.
  std::vector<v1::RunEvent> read_events(std::int64_t run_id, std::uint64_t after_seq, int limit,
                                        bool no_progress = false);
  std::optional<StoredCheckpoint> latest_checkpoint(std::int64_t run_id);

  Page<v1::Encounter> list_conjunctions(const v1::ListConjunctionsRequest& request);
  // One conjunction (kind encounter) by sequence number, with names; empty when there is none.
  std::optional<v1::Encounter> conjunction(std::int64_t run_id, std::uint64_t seq);
  v1::RunStats run_stats(const v1::GetRunStatsRequest& request, double run_length_s);
  // By fragment id; the page token is the offset (std::invalid_argument for a token not from a page).
  Page<v1::Fragment> list_fragments(const v1::ListFragmentsRequest& request);
  // The run's launches, re-entries and breakups (store_event_times.cpp).
  EventTimes event_times(std::int64_t run_id);

  // Population snapshots (store_snapshots.cpp), through the writer thread in order with the events;
  // encoded there (server/snapshot_codec.hpp) and stored idempotently by (run, step).
  void append_snapshot(std::int64_t run_id, std::shared_ptr<const PopulationSnapshot> snapshot);
  // By step; the page token is the last step of the previous page (std::invalid_argument for a bad one).
  Page<StoredSnapshotInfo> list_snapshots(std::int64_t run_id, int page_size, const std::string& page_token);
  // The last snapshot at or before `step` (the newest when nullopt), decoded; nullopt when none.
  std::optional<PopulationSnapshot> read_snapshot(std::int64_t run_id, std::optional<std::int64_t> step);
  // Its row alone.
  std::optional<StoredSnapshotInfo> snapshot_info(std::int64_t run_id, std::optional<std::int64_t> step);

  // Rows written by the writer thread since the store opened (events), for the benchmark.
  std::uint64_t events_written() const;
  // CPU seconds the writer thread spent writing (a figure of its cost that other load does not skew).
  double writer_cpu_s() const;

 private:
  struct Pending;
  struct WriterStatements;
  void writer_loop();
  void enqueue(Pending p);  // one item for the writer, in order
  void write_batch(std::vector<Pending>& batch, WriterStatements& statements);
  class Lease;  // a pooled connection for reads and run updates
  sqlite3* acquire();
  void release(sqlite3* db);

  void check_at_open();
  void report_write_failure(const std::vector<Pending>& batch, const std::string& error);
  void throw_if_failing_for_test();

  std::string path_;
  std::chrono::milliseconds min_checkpoint_interval_;
  StoreHealth health_;
  std::atomic<std::uint64_t> min_free_bytes_{64ull << 20};
  std::map<std::int64_t, std::string> quarantined_;
  std::mutex handler_mutex_;
  std::function<void(std::int64_t, const std::string&)> write_failure_handler_;
  std::mutex test_fault_mutex_;
  std::string test_fault_;
  sqlite3* writer_db_ = nullptr;  // the writer thread's connection
  std::mutex pool_mutex_;
  std::vector<sqlite3*> pool_;  // idle reader connections
  std::vector<sqlite3*> all_;   // every connection, closed at the end

  std::mutex queue_mutex_;
  std::condition_variable queue_cv_;
  std::condition_variable flushed_cv_;
  std::deque<Pending> queue_;
  std::uint64_t appended_ = 0;
  std::uint64_t committed_ = 0;
  int flush_waiters_ = 0;
  bool stopping_ = false;
  std::uint64_t events_written_ = 0;
  double writer_cpu_s_ = 0.0;
  std::thread writer_;
};

bool is_terminal(v1::RunState state);

}  // namespace kessler::server
