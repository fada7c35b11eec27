// kessler run SCENARIO --local: the command's options; the run itself is local_run.cpp's.
#include <memory>

#include "client/commands/local_run.hpp"

namespace kessler::cli {

CommandRun setup_run(CLI::App& command, GlobalOptions& global) {
  auto o = std::make_shared<LocalRunOptions>();
  command.add_option("SCENARIO", o->scenario_path, "a scenario file, YAML or JSON (see deploy/scenarios/)")
      ->required();
  command.add_flag("--local", o->local, "run in this process (no daemon); required");
  command
      .add_option("--threads", o->build.threads,
                  "OpenMP threads (0, the default: all cores); results are identical for any T")
      ->option_text("T")
      ->check(CLI::Range(0, 4096));
  command
      .add_option("--checkpoint-dir", o->checkpoint_dir,
                  "write checkpoints into DIR (checkpoint-<step>.ckpt; the last three are kept)")
      ->option_text("DIR");
  command.add_option("--resume", o->resume_path, "continue the scenario's run from a checkpoint it wrote")
      ->option_text("CHECKPOINT");
  command.add_option("--datasets", o->build.datasets_dir, "where the bundled datasets live")
      ->option_text("DIR");
  command
      .add_option("--traffic-plans", o->build.traffic_dir,
                  "where the shipped launch plans live (a scenario's traffic.plans)")
      ->option_text("DIR");
  add_global_options(
      command, global,
      "table (default) or json: one object per line, the first the ingest report (for catalogs), "
      "the last the summary",
      false);
  command.footer(
      "A catalog's ingest report (records read, kept, dropped by reason) comes before the run.\n"
      "Ctrl-C stops at the next step (after a checkpoint when --checkpoint-dir is given).\n"
      "Exit codes: 0 finished, 1 failed or stopped early, 2 bad usage or scenario.");
  return [o, &global] {
    OutputFormat format;
    if (!resolve_output("run", global.output, {"table", "json"}, format)) return kExitUsage;
    return run_local(*o, format);
  };
}

}  // namespace kessler::cli
