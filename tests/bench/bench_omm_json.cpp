// kessler-bench omm-json: reading the real catalog (catalog-2022, 23,939 element sets) as OMM JSON, as
// CelesTrak writes it (one object per element set, numbers as JSON numbers). The 3LE text is converted
// once; the figures are the medians over --repeats of parse_omm_json's wall and CPU time, and of a
// whole ingest's wall time.
//   --repeats R (default 5)  --threads T (default 1)
#include <omp.h>

#include <cstdio>
#include <string>
#include <vector>

#include "core/catalog/bundled_datasets.hpp"
#include "core/catalog/omm.hpp"
#include "tests/bench/bench.hpp"

namespace kessler::bench {
namespace {

constexpr double kRevPerDayPerRadMin = 1440.0 / (2.0 * 3.14159265358979323846);
constexpr double kDegPerRad = 180.0 / 3.14159265358979323846;

std::string omm_json_of(const ElementSetText& sets) {
  std::string out = "[";
  char buf[1024];
  for (std::size_t i = 0; i < sets.sets.size(); ++i) {
    const MeanElements& e = sets.sets[i].elements;
    std::snprintf(buf, sizeof buf,
                  "%s{\"OBJECT_NAME\":\"%s\",\"OBJECT_ID\":\"%s\",\"EPOCH\":\"%s\",\"MEAN_MOTION\":%.8f,"
                  "\"ECCENTRICITY\":%.7f,\"INCLINATION\":%.4f,\"RA_OF_ASC_NODE\":%.4f,"
                  "\"ARG_OF_PERICENTER\":%.4f,\"MEAN_ANOMALY\":%.4f,\"EPHEMERIS_TYPE\":0,"
                  "\"CLASSIFICATION_TYPE\":\"U\",\"NORAD_CAT_ID\":%llu,\"ELEMENT_SET_NO\":999,"
                  "\"REV_AT_EPOCH\":1000,\"BSTAR\":%.5g,\"MEAN_MOTION_DOT\":%.8g,\"MEAN_MOTION_DDOT\":%.5g}",
                  i ? ",\n" : "\n", e.name.c_str(), e.international_designator.c_str(),
                  e.epoch.to_iso8601(6).c_str(), e.mean_motion_rad_min * kRevPerDayPerRadMin, e.eccentricity,
                  e.inclination_rad * kDegPerRad, e.raan_rad * kDegPerRad,
                  e.argument_of_perigee_rad * kDegPerRad, e.mean_anomaly_rad * kDegPerRad,
                  static_cast<unsigned long long>(e.catalog_number), e.bstar_per_earth_radius,
                  e.mean_motion_dot_rad_min2 * kRevPerDayPerRadMin * 1440.0,
                  e.mean_motion_ddot_rad_min3 * kRevPerDayPerRadMin * 1440.0 * 1440.0);
    out += buf;
  }
  return out + "\n]\n";
}

int bench_omm_json(int argc, char** argv) {
  Args args(argc, argv);
  args.allow_only({"--repeats", "--threads"});
  const int repeats = static_cast<int>(args.get_int("--repeats", 5));
  const int threads = static_cast<int>(args.get_int("--threads", 1));
  if (repeats < 1 || threads < 1) {
    std::fprintf(stderr, "kessler-bench omm-json: --repeats and --threads must be positive\n");
    return 2;
  }
  omp_set_num_threads(threads);
  std::string error;
  auto input = load_bundled_catalog("catalog-2022", default_datasets_dir(), &error);
  if (!input) {
    std::fprintf(stderr, "kessler-bench omm-json: %s\n", error.c_str());
    return 1;
  }
  CatalogInput json = *input;
  json.format = CatalogFormat::kOmmJson;
  json.text = omm_json_of(parse_catalog_text(input->text, CatalogFormat::kTle, "catalog"));
  const UtcEpoch start = UtcEpoch::from_calendar(2022, 1, 1, 0, 0, 0);

  // Wall and process CPU time: on a shared machine the CPU time is the steadier figure.
  std::vector<double> parse_s, parse_cpu_s, ingest_s;
  std::size_t sets = 0, kept = 0;
  for (int r = 0; r < repeats; ++r) {
    double t0 = now_s();
    const double c0 = process_cpu_s();
    const ElementSetText parsed = parse_omm_json(json.text, "catalog");
    parse_cpu_s.push_back(process_cpu_s() - c0);
    parse_s.push_back(now_s() - t0);
    sets = parsed.sets.size();
    t0 = now_s();
    const IngestResult ingest = ingest_catalog(json, IngestRules{}, start, 1);
    ingest_s.push_back(now_s() - t0);
    kept = ingest.report.kept;
  }
  JsonLine()
      .add("benchmark", std::string("omm-json"))
      .add("bytes", static_cast<std::int64_t>(json.text.size()))
      .add("element_sets", static_cast<std::int64_t>(sets))
      .add("kept", static_cast<std::int64_t>(kept))
      .add("threads", static_cast<std::int64_t>(threads))
      .add("parse_s", median(parse_s))
      .add("parse_cpu_s", median(parse_cpu_s))
      .add("ingest_s", median(ingest_s))
      .print();
  return 0;
}

}  // namespace

KESSLER_BENCH("omm-json", "reading the real catalog as OMM JSON: parse and whole ingest [s, medians]",
              bench_omm_json);

}  // namespace kessler::bench
