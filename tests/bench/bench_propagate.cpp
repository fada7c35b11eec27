// kessler-bench propagate: the symplectic propagator (--integrator, default blanes_moan4) with the full force
// model (Kepler, J2, C22/S22, drag on the density table, the exponential fit or NRLMSISE-00 with observed
// solar activity (its grid: the day's build happens in the warm-up step, slot grids inside the timing), SRP
// with shadow; drag coupled at every kick or at the step's ends, --drag-coupling) on the leo-19647
// population, repeated to reach --objects (each copy's positions scaled by 1 + 1e-6 copy so no two objects
// coincide), dt = 10 s.
#include <omp.h>
#include <time.h>

#include <algorithm>
#include <cstdio>
#include <iostream>

#include "core/catalog/leo19647.hpp"
#include "core/integration/symplectic_propagator.hpp"
#include "tests/bench/bench.hpp"

namespace kessler::bench {
namespace {

int run(int argc, char** argv) {
  Args args(argc, argv);
  args.allow_only({"--objects", "--steps", "--threads", "--repeats", "--dataset", "--dt", "--atmosphere",
                   "--forces", "--integrator", "--drag-coupling"});
  const auto objects = static_cast<std::size_t>(args.get_int("--objects", 20000));
  const auto steps = args.get_int("--steps", 100);
  const int threads = static_cast<int>(args.get_int("--threads", 1));
  const int repeats = static_cast<int>(args.get_int("--repeats", 5));
  const double dt = args.get_double("--dt", 10.0);
  const std::string dir = args.get("--dataset", std::string(KESSLER_DATASETS_DIR) + "/leo-19647");
  const std::string atmosphere = args.get("--atmosphere", "table");
  if (objects == 0 || steps <= 0 || threads <= 0 || repeats <= 0 || !(dt > 0)) {
    std::cerr << "kessler-bench propagate: --objects, --steps, --threads, --repeats, --dt must be positive\n";
    return 2;
  }
  const std::string integrator =
      args.get("--integrator", std::string(integrator_name(Integrator::kBlanesMoan4)));
  const std::optional<Integrator> composition = integrator_from_name(integrator);
  if (!composition) {
    std::cerr << "kessler-bench propagate: --integrator is yoshida4 or blanes_moan4\n";
    return 2;
  }
  const std::string coupling = args.get("--drag-coupling", "every_kick");
  if (coupling != "every_kick" && coupling != "step_ends") {
    std::cerr << "kessler-bench propagate: --drag-coupling is every_kick or step_ends\n";
    return 2;
  }
  if (atmosphere != "table" && atmosphere != "fit" && atmosphere != "nrlmsise00") {
    std::cerr << "kessler-bench propagate: --atmosphere is 'table', 'fit' or 'nrlmsise00'\n";
    return 2;
  }
  const Population initial = leo19647_repeated(dir, objects);
  ForceModelSettings forces;  // everything on unless --forces lists a subset
  const std::string force_list = args.get("--forces", "kepler,j2,c22,drag,srp");
  forces.kepler = force_list.find("kepler") != std::string::npos;
  forces.j2 = force_list.find("j2") != std::string::npos;
  forces.c22_s22 = force_list.find("c22") != std::string::npos;
  forces.drag = force_list.find("drag") != std::string::npos;
  forces.srp = force_list.find("srp") != std::string::npos;
  forces.atmosphere = atmosphere == "fit"          ? AtmosphereModel::kExponentialFit
                      : atmosphere == "nrlmsise00" ? AtmosphereModel::kNrlmsise00
                                                   : AtmosphereModel::kDensityTable;
  forces.drag_coupling = coupling == "step_ends" ? DragCoupling::kStepEnds : DragCoupling::kEveryKick;
  SymplecticPropagator propagator(forces, leo19647_epoch(), *composition);
  propagator.set_threads(threads);
  std::vector<double> walls, cpus;
  for (int rep = 0; rep < repeats; ++rep) {
    Population p = initial;
    propagator.step(p, 0.0, dt);  // warm-up: first touch, thread pool
    const double start = now_s(), cpu_start = process_cpu_s();
    for (std::int64_t s = 1; s <= steps; ++s) propagator.step(p, s * dt, dt);
    walls.push_back(now_s() - start);
    cpus.push_back(process_cpu_s() - cpu_start);
    std::printf("repeat %d: %.4f s, %.1f ns/object-step\n", rep + 1, walls.back(),
                walls.back() * threads * 1e9 / (static_cast<double>(objects) * steps));
  }
  const double wall = median(walls);
  JsonLine()
      .add("benchmark", std::string("propagate"))
      .add("objects", static_cast<std::int64_t>(objects))
      .add("steps", steps)
      .add("threads", static_cast<std::int64_t>(threads))
      .add("repeats", static_cast<std::int64_t>(repeats))
      .add("dt_s", dt)
      .add("integrator", integrator)
      .add("atmosphere", atmosphere)
      .add("drag_coupling", coupling)
      .add("forces", force_list)
      .add("wall_s", wall)
      .add("wall_min_s", *std::min_element(walls.begin(), walls.end()))
      .add("cpu_s", median(cpus))
      .add("ns_per_object_step", wall * threads * 1e9 / (static_cast<double>(objects) * steps))
      .add("cpu_ns_per_object_step", median(cpus) * 1e9 / (static_cast<double>(objects) * steps))
      .print();
  return 0;
}

}  // namespace

KESSLER_BENCH("propagate",
              "one propagator step, full force model, leo-19647 repeated to --objects N; --steps S --threads "
              "T --integrator yoshida4|blanes_moan4 "
              "[--repeats R --atmosphere table|fit|nrlmsise00 --drag-coupling every_kick|step_ends "
              "--forces kepler,j2,c22,drag,srp]",
              run);

}  // namespace kessler::bench
