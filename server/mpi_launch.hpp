// A run handed to an MPI job (kesslerd --mpi-launcher): the daemon writes the scenario (and the
// checkpoint it resumes from) to a private directory, starts `<launcher words> <kessler-mpi> scenario.pb
// --event-stream ...` in a process group of its own, and replays the records rank 0 writes on its stdout
// into the run's sinks (core/simulation/event_stream.hpp): the store, event hub, limits and digests see
// what an in-process run hands them. Stops and cancels go to the ranks as lines on the job's stdin.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/simulation/events.hpp"
#include "core/simulation/simulation.hpp"
#include "kessler/v1/scenario.pb.h"

namespace kessler::server {

struct MpiLaunch {
  std::vector<std::string> launcher;  // "mpirun -np 8 --hostfile H" in words; empty: runs in-process
  std::string program;                // kessler-mpi
  // Where each run's directory is made; the ranks read the scenario there, so on a cluster it must be
  // on a filesystem every node sees. Empty: the system's temporary directory.
  std::string work_dir;
  // A job that ends without the run's end (a rank or node lost) is started again from the run's last
  // checkpoint this many times before the run fails (--mpi-retries).
  int retries = 0;
};

// What run_on_ranks throws when the job ended without the run's end or a failure of the run's own (a
// rank killed, a node lost, the launcher refused): computing the run again may succeed.
struct MpiJobLost : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The launcher line in words (split at blanks; '...' and "..." group words). nullopt with `error` set
// when a quote is not closed or there are no words.
std::optional<std::vector<std::string>> split_launcher(const std::string& line, std::string& error);

// kessler-mpi beside the running executable (kesslerd's build and install directories hold both).
std::string default_mpi_program();

struct RanksRun {
  std::int64_t run_id = 0;  // for the daemon's log line
  const v1::Scenario* scenario = nullptr;
  const std::string* checkpoint = nullptr;  // resume from these bytes; null: a fresh run
  std::int64_t checkpoint_step = 0;
  int threads = 0;                        // per rank; 0: OpenMP's default
  std::string datasets_dir, traffic_dir;  // empty: kessler-mpi's defaults
};

// Runs `run` on the MPI job and hands its events to `sink` as Simulation::run would, returning the
// summary; a failure (the job could not start, a rank died, the run failed) calls sink.on_failed and
// throws std::runtime_error naming it, with the end of the job's stderr. `control`: stop_after_checkpoint
// sends one stop line, cancel a second.
RunSummary run_on_ranks(const MpiLaunch& launch, const RanksRun& run, EventSink& sink, RunControl& control);

}  // namespace kessler::server
