// The web tests' shared run: the crossings scenario (crossings.hpp) run to its end on a RunManager in
// this process, once per test program.
#pragma once

#include <chrono>
#include <memory>
#include <stdexcept>
#include <thread>

#include "core/scenario/run_builder.hpp"
#include "server/run_manager.hpp"
#include "server/store.hpp"
#include "tests/service/temp_dir.hpp"
#include "tests/web/crossings.hpp"

namespace kessler::test {

// Waits until the run has ended (or `until` says so); throws after 120 s.
template <typename Until>
v1::Run wait_for(server::RunManager& manager, std::int64_t run_id, Until until) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (std::chrono::steady_clock::now() < deadline) {
    v1::Run run = manager.get(run_id);
    if (until(run)) {
      manager.store().flush();  // the run's last events, handed to the writer, committed
      return run;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  throw std::runtime_error("run " + std::to_string(run_id) + " did not get there in 120 s");
}

struct InProcessRun {
  InProcessRun() {
    server::ManagerOptions options;
    options.db_path = dir.path() + "/k.db";
    manager = std::make_unique<server::RunManager>(options);
    v1::SubmitRunRequest submit;
    submit.set_scenario_text(crossings_scenario());
    run_id = manager->submit(submit).id();
    run = wait_for(*manager, run_id, [](const v1::Run& r) { return server::is_terminal(r.state()); });
    if (run.state() != v1::RUN_STATE_SUCCEEDED)
      throw std::runtime_error("the crossings run failed: " + run.error());
  }
  TempDir dir;
  std::unique_ptr<server::RunManager> manager;
  std::int64_t run_id = 0;
  v1::Run run;
};

inline InProcessRun& shared_run() {
  static InProcessRun run;
  return run;
}

}  // namespace kessler::test
