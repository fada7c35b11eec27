// Figure 2 (the paper's Fig. 4): conjunctions over time at kappa 1, 2, 5 and 10 (cumulative), and the
// run's total against kappa. Collisions count as conjunctions, evasions do not (GetRunStats' rule).
#include <algorithm>
#include <cstdio>
#include <utility>

#include "server/figures/figure.hpp"

namespace kessler::server::figures {
namespace {

using nlohmann::json;

std::string kappa_label(double kappa) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "kappa <= %g", kappa);
  return buf;
}

// The cumulative count of each kappa series at the end of each bin the run has reached, from 0.
json run_rows(const RunData& data, const TimeAxis& axis) {
  json rows = json::array();
  const double reached = run_reached_s(data);
  const double bin = data.stats.time_bin_s();
  for (const v1::KappaSeries& series : data.stats.by_kappa()) {
    rows.push_back({{"run", data.label}, {"kappa", kappa_label(series.kappa())}, {"t", 0.0}, {"n", 0}});
    for (int b = 0; b < series.cumulative_size() && b < data.stats.bin_start_s_size(); ++b) {
      const double start = data.stats.bin_start_s(b);
      if (start >= reached && b > 0) break;
      const double end = std::min(start + bin, std::max(reached, start));
      rows.push_back({{"run", data.label},
                      {"kappa", kappa_label(series.kappa())},
                      {"t", end / axis.seconds_per_unit},
                      {"n", series.cumulative(b)}});
    }
  }
  return rows;
}

// The members' 5-95 % band of a sample at kappa index k (the mean where an older store has none).
std::pair<double, double> band_of(const v1::EnsembleSample& s, int k) {
  if (k >= s.conjunctions_p05_size() || k >= s.conjunctions_p95_size())
    return {s.conjunctions_mean(k), s.conjunctions_mean(k)};
  return {s.conjunctions_p05(k), s.conjunctions_p95(k)};
}

json ensemble_rows(const v1::EnsembleReport& report, const TimeAxis& axis) {
  json rows = json::array();
  for (const v1::EnsembleSample& s : report.series())
    for (int k = 0; k < report.kappas_size() && k < s.conjunctions_mean_size(); ++k) {
      const auto [p05, p95] = band_of(s, k);
      rows.push_back({{"run", "mean"},
                      {"kappa", kappa_label(report.kappas(k))},
                      {"t", s.t() / axis.seconds_per_unit},
                      {"n", s.conjunctions_mean(k)},
                      {"p05", p05},
                      {"p95", p95}});
    }
  return rows;
}

// An ensemble's spec: its encoding drawn as lines over the members' 5-95 % bands (fields p05, p95).
void draw_with_bands(json& spec) {
  json band_encoding = spec["encoding"];
  band_encoding["y"] = {
      {"field", "p05"}, {"type", "quantitative"}, {"title", spec["encoding"]["y"]["title"]}};
  band_encoding["y2"] = {{"field", "p95"}};
  band_encoding.erase("tooltip");
  json band = {{"mark", {{"type", "area"}, {"opacity", 0.2}}}, {"encoding", band_encoding}};
  json line = {{"mark", spec["mark"]}, {"encoding", spec["encoding"]}};
  if (line["mark"].contains("interpolate")) band["mark"]["interpolate"] = line["mark"]["interpolate"];
  line["encoding"]["tooltip"].push_back({{"field", "p05"}, {"title", "5 %"}});
  line["encoding"]["tooltip"].push_back({{"field", "p95"}, {"title", "95 %"}});
  spec.erase("mark");
  spec.erase("encoding");
  spec["layer"] = json::array({band, line});
}

json kappa_sort(const FigureSubject& subject) {
  std::vector<double> kappas;
  if (subject.ensemble) kappas.assign(subject.ensemble->kappas().begin(), subject.ensemble->kappas().end());
  for (const RunData& r : subject.runs)
    for (const auto& s : r.stats.by_kappa()) kappas.push_back(s.kappa());
  std::sort(kappas.begin(), kappas.end());
  kappas.erase(std::unique(kappas.begin(), kappas.end()), kappas.end());
  json order = json::array();
  for (double k : kappas) order.push_back(kappa_label(k));
  return order;
}

}  // namespace

json conjunctions_over_time(const FigureSubject& subject) {
  double longest = 0;
  for (const RunData& r : subject.runs) longest = std::max(longest, run_length_s(r.stats));
  if (subject.ensemble && subject.ensemble->series_size() > 0)
    longest = subject.ensemble->series(subject.ensemble->series_size() - 1).t();
  const TimeAxis axis = time_axis_for(longest);
  json rows = json::array();
  if (subject.ensemble) {
    rows = ensemble_rows(*subject.ensemble, axis);
  } else {
    for (const RunData& r : subject.runs)
      for (auto& row : run_rows(r, axis)) rows.push_back(std::move(row));
  }
  if (rows.empty()) return nullptr;
  json spec =
      base_spec("Conjunctions over time by kappa",
                subject.ensemble ? "cumulative, mean over the ensemble's succeeded members; bands: 5-95 %"
                                 : "cumulative; collisions included, evasions not");
  spec["data"] = {{"values", rows}};
  spec["mark"] = {{"type", "line"}, {"interpolate", "step-after"}};
  spec["encoding"] = {
      {"x", {{"field", "t"}, {"type", "quantitative"}, {"title", axis.title}}},
      {"y", {{"field", "n"}, {"type", "quantitative"}, {"title", "conjunctions (cumulative)"}}},
      {"color",
       {{"field", "kappa"}, {"type", "nominal"}, {"title", "threshold"}, {"sort", kappa_sort(subject)}}},
      {"tooltip", json::array({{{"field", "run"}},
                               {{"field", "kappa"}},
                               {{"field", "t"}, {"title", axis.title}},
                               {{"field", "n"}, {"title", "conjunctions"}}})},
  };
  if (subject.runs.size() > 1) spec["encoding"]["strokeDash"] = {{"field", "run"}, {"type", "nominal"}};
  if (subject.ensemble) draw_with_bands(spec);
  return spec;
}

json conjunctions_vs_kappa(const FigureSubject& subject) {
  json rows = json::array();
  if (subject.ensemble) {
    const auto& report = *subject.ensemble;
    if (report.series_size() == 0) return nullptr;
    const v1::EnsembleSample& last = report.series(report.series_size() - 1);
    for (int k = 0; k < report.kappas_size() && k < last.conjunctions_mean_size(); ++k) {
      const auto [p05, p95] = band_of(last, k);
      rows.push_back({{"run", "mean"},
                      {"kappa", report.kappas(k)},
                      {"n", last.conjunctions_mean(k)},
                      {"p05", p05},
                      {"p95", p95}});
    }
  }
  for (const RunData& r : subject.runs)
    for (const v1::KappaSeries& s : r.kappa_sweep.by_kappa())
      rows.push_back({{"run", r.label},
                      {"kappa", s.kappa()},
                      {"n", s.cumulative_size() ? s.cumulative(s.cumulative_size() - 1) : 0}});
  if (rows.empty()) return nullptr;
  json spec = base_spec("Conjunctions against kappa",
                        subject.ensemble ? "over the whole run, mean over the ensemble; band: 5-95 %"
                                         : "over the whole run (so far, while it runs)");
  spec["data"] = {{"values", rows}};
  spec["mark"] = {{"type", "line"}, {"point", true}};
  spec["encoding"] = {
      {"x", {{"field", "kappa"}, {"type", "quantitative"}, {"title", "kappa (miss distance / (r1 + r2))"}}},
      {"y", {{"field", "n"}, {"type", "quantitative"}, {"title", "conjunctions"}}},
      {"color", {{"field", "run"}, {"type", "nominal"}, {"title", "run"}}},
      {"tooltip",
       json::array({{{"field", "run"}}, {{"field", "kappa"}}, {{"field", "n"}, {"title", "conjunctions"}}})},
  };
  if (subject.ensemble) draw_with_bands(spec);
  return spec;
}

}  // namespace kessler::server::figures
