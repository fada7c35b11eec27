// kessler-bench decay-history: decay held against what re-entered. Two checks, one JSON line:
//  1. A catalog with a known outcome: --scenario (default deploy/scenarios/decay-history-2019.yaml: the
//     2019-03-19 catalog, no launches, breakups or screening, NRLMSISE-00 on observed solar activity, to
//     2021-01-19) through the core loop; its burn-ups against the DECAY dates of the bundled SATCAT of
//     2021-01-19 (core/decay/reentry_history.hpp): re-entries per month, recall, precision, decay-date
//     error; and by perigee band at the start.
//  2. The Iridium 33 / Cosmos 2251 clouds (iridium_cosmos_cloud.hpp) from 2009 to the SATCAT's date in
//     the same atmosphere: of the fragments on orbit on 2012-01-01 (when the catalogue had caught up with
//     the clouds), the fraction still on orbit each 1 January, the model's (SBM, Lc >= 10 cm) against the
//     SATCAT's catalogued pieces (designators 1997-051 and 1993-036, DEBRIS, numbers above 33,000, in the
//     catalogue by then: DEBUT).
// Options: --scenario FILE  --threads T  --dt S and --end ISO8601 (override the scenario's)  --max-apogee-km
// K (a quicker subset)  --ballistic fitted|bstar  --signal ndot|bstar (the fit's first signal)  --clouds
// on|off
// --cloud-dt S (default 120)  --satcat PATH.
#include <omp.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <unordered_map>

#include "core/catalog/bundled_datasets.hpp"
#include "core/catalog/satcat.hpp"
#include "core/decay/reentry_history.hpp"
#include "core/physics/constants.hpp"
#include "core/scenario/run_builder.hpp"
#include "tests/bench/bench.hpp"
#include "tests/bench/iridium_cosmos_cloud.hpp"

namespace kessler::bench {
namespace {

class BurnUpSink final : public NullSink {
 public:
  void on_burn_up(std::uint64_t, const BurnUp& b) override { burn_up_s[b.id] = b.time_s; }
  void on_progress(std::uint64_t, const Progress& p) override {
    std::fprintf(stderr, "catalog day %.0f: %llu objects, %.0f s wall\n", p.sim_time_s / 86400.0,
                 static_cast<unsigned long long>(p.objects_alive), p.wall_s);
  }
  void on_failed(const std::string& reason) override { failure = reason; }
  std::map<ObjectId, double> burn_up_s;
  std::string failure;
};

// Perigee altitude [km] over the equatorial radius of an osculating state.
double perigee_km(const Eigen::Vector3d& r, const Eigen::Vector3d& v) {
  const double mu = constants::kEarthMu_m3_s2;
  const double a = 1.0 / (2.0 / r.norm() - v.squaredNorm() / mu);
  const Eigen::Vector3d e = ((v.squaredNorm() - mu / r.norm()) * r - r.dot(v) * v) / mu;
  return (a * (1.0 - e.norm()) - constants::kEarthEquatorialRadius_m) * 1e-3;
}

// Is a SATCAT entry a catalogued fragment of the 2009 collision from this parent's launch?
bool cloud_piece(ObjectId id, const SatcatEntry& e, const std::string& designator) {
  return id > 33000 && e.object_type == "DEBRIS" && e.international_designator.rfind(designator, 0) == 0;
}

double median_of(std::vector<double> v) {
  return v.empty() ? 0.0 : median(std::move(v));
}

struct CatalogCheck {
  ReentryComparison comparison;
  // The catalogued clouds' pieces in the catalog at the start: their fitted Cd A/m.
  std::vector<double> iridium_drag, cosmos_drag;
  std::string fit_report;
  std::map<int, std::pair<std::int64_t, std::int64_t>>
      by_band;  // band's lower edge [km] -> predicted, observed
  double wall_s = 0.0;
};

std::optional<CatalogCheck> check_catalog(const Args& args, const SatcatTable& satcat,
                                          const std::unordered_map<ObjectId, UtcEpoch>& decays, int threads) {
  const std::string path =
      args.get("--scenario", std::string(KESSLER_DATASETS_DIR) + "/../scenarios/decay-history-2019.yaml");
  v1::Scenario scenario;
  auto error = load_scenario_file(path, scenario);
  if (!error && args.has("--dt")) scenario.set_dt_s(args.get_double("--dt", 120.0));
  if (!error && args.has("--end")) scenario.set_end_epoch(args.get("--end", ""));
  if (!error && args.has("--max-apogee-km"))
    scenario.mutable_population()->mutable_rules()->set_max_apogee_km(
        args.get_double("--max-apogee-km", 2000));
  const std::string ballistic = args.get("--ballistic", "");
  if (ballistic == "bstar")
    scenario.mutable_population()->set_ballistic_coefficients(v1::BALLISTIC_COEFFICIENTS_BSTAR);
  if (ballistic == "fitted")
    scenario.mutable_population()->set_ballistic_coefficients(v1::BALLISTIC_COEFFICIENTS_FITTED);
  if (!error) error = validate_scenario(scenario);
  if (error) {
    std::fprintf(stderr, "kessler-bench decay-history: %s: %s\n", path.c_str(), error->message().c_str());
    return std::nullopt;
  }
  BuildOptions options;
  options.threads = threads;
  options.checkpoints = false;
  if (args.get("--signal", "ndot") == "bstar") options.ballistic_fit.first_signal = DecaySignal::kSgp4Bstar;
  CatalogCheck out;
  std::optional<IngestReport> report;
  const double t0 = now_s();
  FieldError build_error;
  auto sim = build_simulation(scenario, options, &build_error, &report);
  if (!sim) {
    std::fprintf(stderr, "kessler-bench decay-history: %s\n", build_error.message().c_str());
    return std::nullopt;
  }
  std::fprintf(stderr, "ingest and fit: %.1f s\n%s", now_s() - t0, report ? report->text().c_str() : "");
  if (report && report->drag_fit) out.fit_report = report->text();
  const Population& start = sim->population();
  const std::vector<ObjectId> ids = start.id;
  std::unordered_map<ObjectId, int> band_of;
  for (std::size_t i = 0; i < start.size(); ++i) {
    const double hp = perigee_km(start.state.position(i), start.state.velocity(i));
    band_of[start.id[i]] = hp < 300 ? 200 : hp >= 800 ? 800 : static_cast<int>(hp / 100) * 100;
    const auto e = satcat.entries.find(start.id[i]);
    if (e == satcat.entries.end()) continue;
    if (cloud_piece(e->first, e->second, "1997-051"))
      out.iridium_drag.push_back(start.drag_area_to_mass_m2_kg[i]);
    if (cloud_piece(e->first, e->second, "1993-036"))
      out.cosmos_drag.push_back(start.drag_area_to_mass_m2_kg[i]);
  }
  const SimulationConfig config = to_simulation_config(scenario);
  const UtcEpoch end = config.start_epoch.plus_seconds(config.duration_s);
  BurnUpSink sink;
  RunControl control;
  sim->run(sink, control);
  out.wall_s = now_s() - t0;
  if (!sink.failure.empty()) {
    std::fprintf(stderr, "kessler-bench decay-history: the run failed: %s\n", sink.failure.c_str());
    return std::nullopt;
  }
  out.comparison = compare_reentries(ids, sink.burn_up_s, decays, config.start_epoch, end);
  for (ObjectId id : ids) {
    auto& [predicted, observed] = out.by_band[band_of[id]];
    if (sink.burn_up_s.count(id)) ++predicted;
    const auto d = decays.find(id);
    if (d != decays.end() && d->second.seconds_since(config.start_epoch) > 0.0 &&
        d->second.seconds_since(end) <= 0.0)
      ++observed;
  }
  return out;
}

struct CloudCheck {
  // The model's fragments on orbit at `survivors_at` (the catalog check's start): their Cd A/m.
  std::vector<double> iridium_drag, cosmos_drag;
  std::vector<int> years;
  std::vector<double> model_iridium, model_cosmos, catalogue_iridium, catalogue_cosmos;
  double error_max = 0.0, wall_s = 0.0;
};

// The catalogued fragments of each parent in the catalogue by `base` (DEBUT), and their decay dates
// (nullopt: still on orbit).
std::vector<std::optional<UtcEpoch>> catalogued_cloud(const SatcatTable& satcat,
                                                      const std::string& designator, const UtcEpoch& base) {
  std::vector<std::optional<UtcEpoch>> out;
  for (const auto& [id, e] : satcat.entries)
    if (cloud_piece(id, e, designator) && (!e.debut || e.debut->seconds_since(base) <= 0.0))
      out.push_back(e.decay);
  return out;
}

std::optional<CloudCheck> check_clouds(const Args& args, const SatcatTable& satcat, const UtcEpoch& to,
                                       const UtcEpoch& survivors_at, int threads) {
  CloudRunOptions o;
  o.to = to;
  o.dt_s = args.get_double("--cloud-dt", 120.0);
  o.threads = threads;
  o.tle_path = std::string(KESSLER_BENCH_TEST_DATA_DIR) +
               "/iridium_cosmos/iridium33_cosmos2251_last_pre_collision.tle";
  o.force_model.atmosphere = AtmosphereModel::kNrlmsise00;
  o.force_model.drag_coupling = DragCoupling::kStepEnds;
  CloudRun run;
  try {
    run = run_iridium_cosmos_cloud(o);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "kessler-bench decay-history: %s\n", e.what());
    return std::nullopt;
  }
  std::vector<std::optional<UtcEpoch>> model_iridium, model_cosmos;
  for (const auto& [id, parent] : run.parent) {
    const auto b = run.burn_up_s.find(id);
    std::optional<UtcEpoch> removed;
    if (b != run.burn_up_s.end()) removed = run.start.plus_seconds(b->second);
    (parent == kIridium33 ? model_iridium : model_cosmos).push_back(removed);
  }
  const UtcEpoch base = UtcEpoch::from_calendar(2012, 1, 1, 0, 0, 0.0);
  const auto cat_iridium = catalogued_cloud(satcat, "1997-051", base);
  const auto cat_cosmos = catalogued_cloud(satcat, "1993-036", base);
  CloudCheck out;
  out.wall_s = run.wall_s;
  const double survivors_s = survivors_at.seconds_since(run.start);
  for (const auto& [id, parent] : run.parent) {
    const auto b = run.burn_up_s.find(id);
    if (b != run.burn_up_s.end() && b->second <= survivors_s) continue;
    (parent == kIridium33 ? out.iridium_drag : out.cosmos_drag).push_back(run.drag_area_to_mass_m2_kg.at(id));
  }
  for (int year = 2013;; ++year) {
    const UtcEpoch at = UtcEpoch::from_calendar(year, 1, 1, 0, 0, 0.0);
    if (at.seconds_since(to) > 0.0) break;
    out.years.push_back(year);
    out.model_iridium.push_back(fraction_still_on_orbit(model_iridium, base, at));
    out.model_cosmos.push_back(fraction_still_on_orbit(model_cosmos, base, at));
    out.catalogue_iridium.push_back(fraction_still_on_orbit(cat_iridium, base, at));
    out.catalogue_cosmos.push_back(fraction_still_on_orbit(cat_cosmos, base, at));
    out.error_max =
        std::max({out.error_max, std::fabs(out.model_iridium.back() - out.catalogue_iridium.back()),
                  std::fabs(out.model_cosmos.back() - out.catalogue_cosmos.back())});
    std::fprintf(stderr,
                 "%d-01-01 on orbit since 2012: Iridium 33 model %.3f catalogue %.3f, Cosmos 2251 model %.3f "
                 "catalogue %.3f\n",
                 year, out.model_iridium.back(), out.catalogue_iridium.back(), out.model_cosmos.back(),
                 out.catalogue_cosmos.back());
  }
  return out;
}

int bench_decay_history(int argc, char** argv) {
  Args args(argc, argv);
  args.allow_only({"--scenario", "--threads", "--dt", "--end", "--max-apogee-km", "--ballistic", "--signal",
                   "--clouds", "--cloud-dt", "--satcat"});
  const int threads = static_cast<int>(args.get_int("--threads", 2));
  if (threads < 1) {
    std::fprintf(stderr, "kessler-bench decay-history: --threads must be positive\n");
    return 2;
  }
  const std::string ballistic = args.get("--ballistic", "fitted"), signal = args.get("--signal", "ndot");
  const std::string clouds = args.get("--clouds", "on");
  if ((ballistic != "fitted" && ballistic != "bstar") || (signal != "ndot" && signal != "bstar") ||
      (clouds != "on" && clouds != "off")) {
    std::fprintf(
        stderr,
        "kessler-bench decay-history: --ballistic fitted|bstar, --signal ndot|bstar, --clouds on|off\n");
    return 2;
  }
  omp_set_num_threads(threads);
  std::string why;
  const std::string satcat_path =
      args.get("--satcat", default_datasets_dir() + "/catalog/spacetrack_satcat_2021-01-19.csv.gz");
  const auto satcat_text = read_catalog_file(satcat_path, &why);
  if (!satcat_text) {
    std::fprintf(stderr, "kessler-bench decay-history: %s\n", why.c_str());
    return 2;
  }
  const SatcatTable satcat = parse_satcat_csv(*satcat_text, satcat_path);
  std::unordered_map<ObjectId, UtcEpoch> decays;
  for (const auto& [id, e] : satcat.entries)
    if (e.decay) decays.emplace(id, *e.decay);

  const auto catalog = check_catalog(args, satcat, decays, threads);
  if (!catalog) return 1;
  const ReentryComparison& c = catalog->comparison;
  for (const ReentryMonth& m : c.by_month)
    std::fprintf(stderr, "%s: predicted %lld, observed %lld\n", m.month.c_str(),
                 static_cast<long long>(m.predicted), static_cast<long long>(m.observed));
  JsonLine line;
  line.add("benchmark", std::string("decay-history"))
      .add("objects", c.simulated)
      .add("reentries_predicted", c.predicted)
      .add("reentries_observed", c.observed)
      .add("hits", c.hits)
      .add("recall", c.recall)
      .add("precision", c.precision)
      .add("median_decay_date_error", c.median_date_error)
      .add("p90_decay_date_error", c.p90_date_error)
      .add("catalog_wall_s", catalog->wall_s);
  for (const auto& [band, counts] : catalog->by_band) {
    const std::string key = band == 200   ? "below_300"
                            : band == 800 ? "800_up"
                                          : std::to_string(band) + "_" + std::to_string(band + 100);
    line.add("perigee_" + key + "_predicted", counts.first)
        .add("perigee_" + key + "_observed", counts.second);
  }
  if (args.get("--clouds", "on") == "on") {
    const auto clouds = check_clouds(args, satcat, UtcEpoch::from_calendar(2021, 1, 19, 0, 0, 0.0),
                                     UtcEpoch::from_calendar(2019, 3, 19, 0, 0, 0.0), threads);
    if (!clouds) return 1;
    std::fprintf(
        stderr,
        "Cd A/m [m^2/kg], median of the pieces on orbit on 2019-03-19: Iridium 33 catalogue (fitted) "
        "%.3f of %zu, model (SBM) %.3f of %zu; Cosmos 2251 catalogue %.3f of %zu, model %.3f of %zu\n",
        median_of(catalog->iridium_drag), catalog->iridium_drag.size(), median_of(clouds->iridium_drag),
        clouds->iridium_drag.size(), median_of(catalog->cosmos_drag), catalog->cosmos_drag.size(),
        median_of(clouds->cosmos_drag), clouds->cosmos_drag.size());
    line.add("cloud_2019_cd_a_m_median_iridium33_catalogue", median_of(catalog->iridium_drag))
        .add("cloud_2019_cd_a_m_median_iridium33_model", median_of(clouds->iridium_drag))
        .add("cloud_2019_cd_a_m_median_cosmos2251_catalogue", median_of(catalog->cosmos_drag))
        .add("cloud_2019_cd_a_m_median_cosmos2251_model", median_of(clouds->cosmos_drag));
    for (std::size_t k = 0; k < clouds->years.size(); ++k) {
      const std::string y = std::to_string(clouds->years[k]);
      line.add("cloud_" + y + "_iridium33_model", clouds->model_iridium[k])
          .add("cloud_" + y + "_iridium33_catalogue", clouds->catalogue_iridium[k])
          .add("cloud_" + y + "_cosmos2251_model", clouds->model_cosmos[k])
          .add("cloud_" + y + "_cosmos2251_catalogue", clouds->catalogue_cosmos[k]);
    }
    line.add("cloud_fraction_error_max", clouds->error_max).add("cloud_wall_s", clouds->wall_s);
  }
  line.print();
  return 0;
}

}  // namespace

KESSLER_BENCH(
    "decay-history",
    "decay against history: the 2019 catalog to 2021-01-19 (re-entries, recall, precision, "
    "decay-date error against the SATCAT) and the Iridium/Cosmos clouds 2012-2021; --scenario FILE "
    "--threads T --dt S --max-apogee-km K --ballistic fitted|bstar --signal ndot|bstar --clouds on|off",
    bench_decay_history);

}  // namespace kessler::bench
