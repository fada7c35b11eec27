// What the daemon does, without the wire: submissions, run lifecycles (queue, run, resume, cancel),
// watching and queries, over the Store, the EventHub of each live run and the Scheduler. The gRPC
// layer (grpc_service) only translates requests and ServiceError to and from the wire.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>

#include "core/simulation/events.hpp"
#include "core/simulation/simulation.hpp"
#include "kessler/v1/service.pb.h"
#include "server/event_hub.hpp"
#include "server/mpi_launch.hpp"
#include "server/run_limits.hpp"
#include "server/run_protos.hpp"
#include "server/scheduler.hpp"
#include "server/store.hpp"

namespace kessler::server {

// A request the daemon refuses, with the status it means.
struct ServiceError : std::runtime_error {
  enum class Code {
    kInvalidArgument,
    kNotFound,
    kFailedPrecondition,
    kResourceExhausted,
    kUnavailable,
    kInternal
  };
  ServiceError(Code c, const std::string& message, std::string path = {})
      : std::runtime_error(message), code(c), field_path(std::move(path)) {}
  Code code;
  std::string field_path;  // for kInvalidArgument: the scenario field at fault
};

struct ManagerOptions {
  std::string db_path = "var/kessler.db";
  int runs_at_once = 1;
  int threads_per_run = 0;  // 0: OpenMP's default
  std::size_t queue_limit = 1000;
  std::uint64_t max_ensemble_members = 1000;  // SubmitEnsemble takes 1..this many members
  std::string datasets_dir;                   // empty: the build's bundled datasets
  std::string traffic_dir;                    // shipped launch plans; empty: the build's deploy/traffic
  std::size_t hub_capacity = 65536;
  // The store writes a run's checkpoints at most this often (a newer one replaces a waiting one);
  // a crash then costs at most this much more recomputation. SIGTERM and run ends write at once.
  std::chrono::milliseconds min_checkpoint_interval{1000};
  // How long the relay gathers the simulation's events before handing a batch to hub and store: the
  // latency watchers see, traded against wake-ups (10 ms cost the bench's 10 watchers 0.37 s of CPU
  // per 2 s run, 50 ms 0.20 s).
  std::chrono::milliseconds relay_gather{50};
  // Applied to each run's core configuration after the scenario's (tests: settings no scenario field
  // reaches). Empty: none.
  std::function<void(SimulationConfig&)> adjust_config;
  // Per-run limits checked at submission, and the stored events a run may emit (run_limits.hpp).
  RunLimits limits;
  // While the store cannot write, how often a small write probes whether it can again.
  std::chrono::milliseconds store_probe_interval{1000};
  // Runs computed by an MPI job (server/mpi_launch.hpp) when the launcher is given; adjust_config
  // does not reach them.
  MpiLaunch mpi;
};

// Allocator settings for a process that hosts runs: blocks up to 32 MB come from the heap and freed
// memory stays for reuse up to 64 MB, instead of glibc's adaptive thresholds. A run takes a
// checkpoint (MBs, built in growing buffers and freed at once) every few dozen steps; with the
// defaults those pages went back to the system and were faulted in again each time, which cost a
// third of the checkpoints' time (0.45 s of a 2.2 s run in kessler-bench service). Call once, early.
void tune_allocator_for_runs();

// Empties the scenario's inline population data (catalog text, SATCAT, active list, state table,
// inline launch plan) and returns their size in bytes: what GetRun leaves out by default.
std::uint64_t strip_inline_data(v1::Scenario& scenario);

class RunManager {
 public:
  // Opens the store and resumes runs a previous daemon left running or queued.
  explicit RunManager(const ManagerOptions& options);
  ~RunManager();

  // `submitter`: the caller's token name ("" without tokens), recorded with the run. A request_id the
  // submitter used before returns that run, whatever the scenario.
  v1::Run submit(const v1::SubmitRunRequest& request, const std::string& submitter = "");
  // The run with its scenario whole.
  v1::Run get(std::int64_t run_id);
  // GetRun: the scenario without its inline population data unless the request asks for it.
  v1::Run get(const v1::GetRunRequest& request);
  // `submitter`: only this submitter's runs (nullptr: everyone's).
  v1::ListRunsResponse list(const v1::ListRunsRequest& request, const std::string* submitter = nullptr);
  v1::Run cancel(std::int64_t run_id);
  // A failed or cancelled run queued again, to continue from its last checkpoint (ResumeRun).
  v1::Run resume(std::int64_t run_id);
  void remove(std::int64_t run_id);
  v1::ListConjunctionsResponse conjunctions(const v1::ListConjunctionsRequest& request);
  // One conjunction as a CDM (server/conjunction_assessment.cpp).
  v1::ConjunctionCdm conjunction_cdm(const v1::GetConjunctionCdmRequest& request);
  v1::RunStats stats(const v1::GetRunStatsRequest& request);
  v1::ListFragmentsResponse fragments(const v1::ListFragmentsRequest& request);

  // Population snapshots (server/run_snapshots.cpp): the RPCs, and the read path of the figures
  // (server/figures/): the decoded snapshot at or before a step (the newest when nullopt; nullopt when
  // the run has none), and the rows of every stored snapshot. NOT_FOUND for an unknown run.
  v1::ListSnapshotsResponse list_snapshots(const v1::ListSnapshotsRequest& request);
  v1::GetSnapshotResponse get_snapshot(const v1::GetSnapshotRequest& request);
  std::optional<PopulationSnapshot> population_snapshot(std::int64_t run_id,
                                                        std::optional<std::int64_t> step);
  std::vector<StoredSnapshotInfo> snapshot_steps(std::int64_t run_id);

  // Ensembles (server/ensembles.cpp).
  v1::EnsembleReport submit_ensemble(const v1::SubmitEnsembleRequest& request,
                                     const std::string& submitter = "");
  v1::EnsembleReport get_ensemble(const v1::GetEnsembleRequest& request);
  v1::ListEnsemblesResponse list_ensembles(const v1::ListEnsemblesRequest& request,
                                           const std::string* submitter = nullptr);
  v1::EnsembleReport cancel_ensemble(std::int64_t ensemble_id);

  // The figures of a run (with runs compared beside it) or an ensemble (server/figures/figures.cpp).
  v1::GetFiguresResponse figures(const v1::GetFiguresRequest& request);

  // Streams the run's events after request.after_seq through `write` (false: the client has gone)
  // until the run ends, `stop()` turns true or the daemon shuts down (ServiceError kUnavailable).
  // `more` tells the writer that another event follows at once.
  using WriteEvent = std::function<bool(const v1::RunEvent& event, bool more)>;
  void watch(const v1::WatchRunRequest& request, const WriteEvent& write, const std::function<bool()>& stop);

  // Graceful stop: running runs checkpoint and stay resumable, watchers end.
  void shutdown();

  Store& store() { return store_; }
  // Faults (run_faults.cpp). Whether the store can write, so submissions are taken; `listener` hears
  // each change (the health service's NOT_SERVING for the API while it cannot). Empty: none.
  bool store_writable();
  void set_store_health_listener(std::function<void(bool writable)> listener);
  // CPU seconds of every run's relay thread so far (for the benchmark).
  double relay_cpu_s() const { return relay_cpu_s_.load(); }

 private:
  // The submitted scenario (given, or parsed from text); INVALID_ARGUMENT when neither or unparsable.
  v1::Scenario read_scenario(const v1::Scenario* scenario, const std::string* text);
  // Validates a submission (an inline catalog is ingested here); its ingest report where it has one.
  std::optional<v1::IngestReport> admit(const v1::Scenario& scenario, int threads);
  // The ensemble without members, series and scenario; NOT_FOUND when there is none.
  v1::EnsembleReport ensemble_head(std::int64_t ensemble_id);
  // The head with its members (no series or scenario).
  v1::EnsembleReport get_ensemble_members(std::int64_t ensemble_id);
  // The run's start epoch and the step a GetSnapshot request asks for (nullopt: the newest).
  static UtcEpoch start_epoch(const v1::Run& run);
  static std::optional<std::int64_t> snapshot_step(const v1::Run& run, const v1::GetSnapshotRequest& r);
  // with_scenario false: without the (possibly large) scenario message.
  v1::Run get(std::int64_t run_id, bool with_scenario);
  void execute(std::int64_t run_id, RunControl& control);
  void execute_run(std::int64_t run_id, RunControl& control);
  std::shared_ptr<EventHub> hub(std::int64_t run_id);
  void finish(std::int64_t run_id, v1::RunState state, const std::string& error,
              const v1::RunSummary* summary);
  // A run whose MPI job was lost goes back to the queue while --mpi-retries allows (false: it fails).
  bool requeue_lost_job(std::int64_t run_id, const RunControl& control, const std::string& why);

  // Faults (run_faults.cpp).
  void recover();  // queues the runs a previous daemon left running or queued
  void note_store_failure(std::int64_t run_id, const std::string& error);
  std::optional<std::string> take_store_failure(std::int64_t run_id);
  void require_writable();  // UNAVAILABLE while the store cannot write
  void require_not_quarantined(std::int64_t run_id);
  void overlay_faults(v1::Run& run);  // an end not yet written, a quarantine
  void record_finish_later(std::int64_t run_id, v1::RunState state, const std::string& error,
                           const v1::RunSummary* summary);
  void write_unrecorded();
  void health_loop();
  void stop_health_thread();
  void start_health_thread();

  struct Unrecorded {
    v1::RunState state = v1::RUN_STATE_FAILED;
    std::string error;
    std::optional<v1::RunSummary> summary;
  };
  std::mutex faults_mutex_;
  std::map<std::int64_t, std::string> store_failures_;  // runs whose events could not be written
  std::map<std::int64_t, Unrecorded> unrecorded_;       // ends the store could not take yet
  bool recovery_pending_ = false;
  bool health_stop_ = false;
  bool reported_writable_ = true;
  std::function<void(bool)> health_listener_;
  std::condition_variable health_cv_;
  std::thread health_thread_;

  ManagerOptions options_;
  Store store_;
  std::mutex requests_mutex_;  // a request id's lookup and its run's creation, together
  std::mutex hubs_mutex_;
  std::map<std::int64_t, std::shared_ptr<EventHub>> hubs_;
  std::map<std::int64_t, int> mpi_retries_used_;  // under hubs_mutex_: lost MPI jobs computed again
  std::atomic<bool> stopping_{false};
  std::atomic<double> relay_cpu_s_{0};
  std::unique_ptr<Scheduler> scheduler_;  // last: its workers use the members above
};

}  // namespace kessler::server
