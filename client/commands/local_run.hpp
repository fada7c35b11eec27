// A scenario run in this process, printed as `kessler run SCENARIO --local` prints it: the ingest report,
// the events (a table, or one JSON object per line) and the summary. kessler-mpi runs it on every rank.
#pragma once

#include <functional>
#include <optional>
#include <string>

#include "client/command.hpp"
#include "core/scenario/run_builder.hpp"

namespace kessler::cli {

struct LocalRunOptions {
  std::string scenario_path, checkpoint_dir, resume_path;
  bool local = false;
  BuildOptions build;
  // The program named in messages ("kessler run: <file>: ...").
  std::string program = "kessler run";
  // False: the run's events go nowhere and no checkpoint file is written (an MPI run's ranks but the
  // first, which compute the same run).
  bool prints = true;
  // Checked once the run is built, before it starts: a message makes the run a usage error (exit 2).
  std::function<std::optional<std::string>(const Simulation&)> check_built;
  // Called with the run's controls before it starts and with null after it (a host's own triggers).
  std::function<void(RunControl*)> on_control;
  // Where a printing run's events and checkpoints go instead of stdout and checkpoint_dir (kessler-mpi
  // --event-stream); nothing is printed then, and checkpoints are taken. Null: printed.
  EventSink* sink = nullptr;
  // Called with the summary of a run that returned (finished, cancelled or stopped at a checkpoint).
  std::function<void(const RunSummary&)> on_summary;
  // scenario_path holds a serialized kessler.v1.Scenario (as kesslerd writes it), not YAML or JSON.
  bool scenario_binary = false;
  // The scenario itself, read already (an ensemble's member); scenario_path then only names it.
  const v1::Scenario* scenario = nullptr;
  // Checkpoints are taken for the sink (a run resumable without a checkpoint directory).
  bool sink_checkpoints = false;
};

// Runs o.scenario_path (o.local must be set) and returns the exit code: 0 finished, 1 failed or stopped
// early, 2 bad usage or scenario.
int run_local(const LocalRunOptions& o, OutputFormat format);

}  // namespace kessler::cli
