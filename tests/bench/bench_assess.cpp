// kessler-bench assess: collision probability and maximum Pc for every conjunction of a leo-19647
// screening (a week at 5 km: ~218,000 events), one core; and CDM export of 10,000 of them.
// The encounters come from the real simulation (its time is not counted), optionally cached in a file
// so that repeated measurements skip it.
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "core/assessment/assess_encounter.hpp"
#include "core/assessment/cdm_export.hpp"
#include "core/catalog/bundled_datasets.hpp"
#include "core/catalog/leo19647.hpp"
#include "core/integration/symplectic_propagator.hpp"
#include "core/simulation/simulation.hpp"
#include "core/simulation/simulation_parts.hpp"
#include "tests/bench/bench.hpp"

namespace kessler::bench {
namespace {

class CollectingSink final : public EventSink {
 public:
  void on_encounter(std::uint64_t, const Encounter& e) override {
    if (e.kind != EncounterKind::kEvasion) encounters.push_back(e);
  }
  void on_burn_up(std::uint64_t, const BurnUp&) override {}
  void on_progress(std::uint64_t, const Progress&) override {}
  void on_checkpoint(std::uint64_t, std::int64_t, const std::string&) override {}
  void on_finished(const RunSummary&) override {}
  void on_failed(const std::string& reason) override {
    std::cerr << "kessler-bench assess: " << reason << "\n";
  }
  std::vector<Encounter> encounters;
};

std::vector<Encounter> simulate(double days, double screen_km, int threads) {
  SimulationConfig config;
  config.duration_s = days * 86400.0;
  config.threads = threads;
  config.checkpoint_every_steps = 0;
  config.checkpoint_every_wall_s = 0.0;
  config.conjunctions.screening_distance_m = screen_km * 1e3;
  config.start_epoch = leo19647_epoch();
  config.force_model.srp = false;
  config.force_model.atmosphere = AtmosphereModel::kExponentialFit;
  Population population = load_leo19647(default_datasets_dir() + "/leo-19647");
  auto propagator =
      std::make_unique<SymplecticPropagator>(config.force_model, config.start_epoch, config.integrator);
  propagator->set_threads(threads);
  Simulation simulation(config, std::move(population), default_parts(config, std::move(propagator)));
  CollectingSink sink;
  RunControl control;
  simulation.run(sink, control);
  return std::move(sink.encounters);
}

// The encounters as their bytes (Encounter is trivially copyable); a cache for repeated measurements.
bool load_cache(const std::string& path, std::vector<Encounter>& out) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::uint64_t n = 0;
  in.read(reinterpret_cast<char*>(&n), sizeof n);
  out.resize(n);
  in.read(reinterpret_cast<char*>(out.data()), static_cast<std::streamsize>(n * sizeof(Encounter)));
  return static_cast<bool>(in);
}

void save_cache(const std::string& path, const std::vector<Encounter>& encounters) {
  std::ofstream out(path, std::ios::binary);
  const std::uint64_t n = encounters.size();
  out.write(reinterpret_cast<const char*>(&n), sizeof n);
  out.write(reinterpret_cast<const char*>(encounters.data()),
            static_cast<std::streamsize>(n * sizeof(Encounter)));
}

int assess(int argc, char** argv) {
  Args args(argc, argv);
  args.allow_only({"--days", "--screen-km", "--threads", "--repeats", "--cache", "--cdms"});
  const double days = args.get_double("--days", 7.0);
  const double screen_km = args.get_double("--screen-km", 5.0);
  const int threads = static_cast<int>(args.get_int("--threads", 1));
  const int repeats = static_cast<int>(args.get_int("--repeats", 5));
  const auto cdms = static_cast<std::size_t>(args.get_int("--cdms", 10000));
  const std::string cache = args.get("--cache", "");
  if (!(days > 0.0) || !(screen_km > 0.0) || threads < 1 || repeats < 1) {
    std::cerr << "kessler-bench assess: --days, --screen-km, --threads and --repeats must be positive\n";
    return 2;
  }
  std::vector<Encounter> encounters;
  const double sim_start = now_s();
  if (cache.empty() || !load_cache(cache, encounters)) {
    encounters = simulate(days, screen_km, threads);
    if (!cache.empty()) save_cache(cache, encounters);
  }
  const double sim_s = now_s() - sim_start;

  // Wall and CPU seconds per round: on a shared machine the CPU time is the one other programs do not
  // inflate.
  std::vector<double> assess_s;
  std::vector<double> assess_cpu_s;
  std::size_t foster = 0;
  std::size_t computed = 0;
  double checksum = 0.0;
  for (int r = 0; r < repeats; ++r) {
    foster = computed = 0;
    checksum = 0.0;
    const double start = now_s();
    const double cpu_start = process_cpu_s();
    for (const Encounter& e : encounters) {
      const assessment::Assessment a = assessment::assess_encounter(e, {}, {});
      computed += a.pc_computed;
      foster += a.method == assessment::PcMethod::kFoster;
      checksum += (a.pc_computed ? a.pc : 0.0) + a.pc_max;
    }
    assess_s.push_back(now_s() - start);
    assess_cpu_s.push_back(process_cpu_s() - cpu_start);
  }

  std::vector<double> export_s;
  std::vector<double> export_cpu_s;
  std::size_t bytes = 0;
  const std::size_t n_cdm = std::min(cdms, encounters.size());
  assessment::CdmExportOptions options;
  options.scenario_epoch = leo19647_epoch();
  options.creation_date = leo19647_epoch();
  for (int r = 0; r < repeats; ++r) {
    bytes = 0;
    const double start = now_s();
    const double cpu_start = process_cpu_s();
    for (std::size_t i = 0; i < n_cdm; ++i) {
      const Encounter& e = encounters[i];
      options.message_id = "BENCH_" + std::to_string(i);
      const assessment::Cdm cdm =
          assessment::cdm_from_encounter(e, {e.id1, "", {}}, {e.id2, "", {}}, options);
      bytes += assessment::write_cdm_kvn(cdm).size();
    }
    export_s.push_back(now_s() - start);
    export_cpu_s.push_back(process_cpu_s() - cpu_start);
  }
  JsonLine line;
  line.add("events", static_cast<std::int64_t>(encounters.size()))
      .add("simulation_s", sim_s)
      .add("assess_s_median", median(assess_s))
      .add("assess_s_min", *std::min_element(assess_s.begin(), assess_s.end()))
      .add("assess_s_max", *std::max_element(assess_s.begin(), assess_s.end()))
      .add("assess_cpu_s_median", median(assess_cpu_s))
      .add("assess_cpu_s_min", *std::min_element(assess_cpu_s.begin(), assess_cpu_s.end()))
      .add("assess_cpu_s_max", *std::max_element(assess_cpu_s.begin(), assess_cpu_s.end()))
      .add("assess_ns_per_event",
           1e9 * median(assess_s) / static_cast<double>(std::max<std::size_t>(encounters.size(), 1)))
      .add("pc_computed", static_cast<std::int64_t>(computed))
      .add("pc_by_foster", static_cast<std::int64_t>(foster))
      .add("checksum", checksum)
      .add("cdm_exported", static_cast<std::int64_t>(n_cdm))
      .add("cdm_export_s_median", median(export_s))
      .add("cdm_export_s_min", *std::min_element(export_s.begin(), export_s.end()))
      .add("cdm_export_s_max", *std::max_element(export_s.begin(), export_s.end()))
      .add("cdm_export_cpu_s_median", median(export_cpu_s))
      .add("cdm_export_cpu_s_min", *std::min_element(export_cpu_s.begin(), export_cpu_s.end()))
      .add("cdm_export_cpu_s_max", *std::max_element(export_cpu_s.begin(), export_cpu_s.end()))
      .add("cdm_bytes", static_cast<std::int64_t>(bytes));
  line.print();
  return 0;
}

}  // namespace

KESSLER_BENCH("assess",
              "Pc and max Pc of every conjunction of leo-19647 screened at 5 km, one core, and CDM export: "
              "[--days 7] [--screen-km 5] [--threads T (the simulation's)] [--repeats 5] [--cache FILE] "
              "[--cdms 10000]",
              assess);

}  // namespace kessler::bench
