// Figure 5 (the paper's Fig. 7): where a run's wall time went, phase by phase (RunSummary.timers).
// An ensemble: each phase's mean over the members that ended, with their 5-95 % range.
#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include "server/figures/figure.hpp"

namespace kessler::server::figures {
namespace {

using nlohmann::json;

std::array<std::pair<const char*, double>, 6> phases(const v1::PhaseTimers& t) {
  return {{{"integrator", t.integrator_s()},
           {"burn-up", t.burn_up_s()},
           {"grid", t.grid_s()},
           {"detection", t.detection_s()},
           {"output", t.output_s()},
           {"checkpoint", t.checkpoint_s()}}};
}

json phase_order() {
  json order = json::array();
  for (const auto& [name, s] : phases(v1::PhaseTimers())) order.push_back(name);
  return order;
}

// Linear interpolation between order statistics (as the ensemble's series).
double percentile(std::vector<double> values, double p) {
  std::sort(values.begin(), values.end());
  const double pos = p * static_cast<double>(values.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(pos));
  const std::size_t hi = std::min(lo + 1, values.size() - 1);
  return values[lo] + (pos - static_cast<double>(lo)) * (values[hi] - values[lo]);
}

json ensemble_spec(const FigureSubject& subject) {
  std::vector<v1::PhaseTimers> timers;
  for (const v1::Run& run : subject.ensemble_members)
    if (run.has_summary()) timers.push_back(run.summary().timers());
  if (timers.empty()) return nullptr;
  json rows = json::array();
  for (std::size_t p = 0; p < 6; ++p) {
    std::vector<double> values;
    values.reserve(timers.size());
    for (const auto& t : timers) values.push_back(phases(t)[p].second);
    double mean = 0;
    for (double v : values) mean += v / static_cast<double>(values.size());
    rows.push_back({{"phase", phases(timers.front())[p].first},
                    {"s", mean},
                    {"p05", percentile(values, 0.05)},
                    {"p95", percentile(values, 0.95)}});
  }
  json spec = base_spec("Runtime by phase",
                        "mean over " + std::to_string(timers.size()) + " members that ended, bars: 5-95 %");
  spec["data"] = {{"values", rows}};
  json x = {{"field", "phase"}, {"type", "nominal"}, {"sort", phase_order()}, {"title", "phase"}};
  spec["layer"] = json::array(
      {{{"mark", "bar"},
        {"encoding",
         {{"x", x},
          {"y", {{"field", "s"}, {"type", "quantitative"}, {"title", "wall time [s]"}}},
          {"tooltip", json::array({{{"field", "phase"}}, {{"field", "s"}, {"title", "mean [s]"}}})}}}},
       {{"mark", "rule"},
        {"encoding",
         {{"x", x}, {"y", {{"field", "p05"}, {"type", "quantitative"}}}, {"y2", {{"field", "p95"}}}}}}});
  return spec;
}

}  // namespace

json runtime_breakdown(const FigureSubject& subject) {
  if (subject.ensemble) return ensemble_spec(subject);
  json rows = json::array();
  for (const RunData& r : subject.runs) {
    if (!r.run.has_summary()) continue;
    for (const auto& [name, s] : phases(r.run.summary().timers()))
      rows.push_back({{"run", r.label}, {"phase", name}, {"s", s}});
  }
  if (rows.empty()) return nullptr;
  json spec = base_spec("Runtime by phase", "wall time of the main loop's phases (the paper's Fig. 7)");
  spec["data"] = {{"values", rows}};
  spec["mark"] = "bar";
  spec["encoding"] = {
      {"x", {{"field", "phase"}, {"type", "nominal"}, {"sort", phase_order()}, {"title", "phase"}}},
      {"y", {{"field", "s"}, {"type", "quantitative"}, {"title", "wall time [s]"}}},
      {"color",
       {{"field", subject.runs.size() > 1 ? "run" : "phase"}, {"type", "nominal"}, {"legend", nullptr}}},
      {"tooltip",
       json::array({{{"field", "run"}}, {{"field", "phase"}}, {{"field", "s"}, {"title", "seconds"}}})},
  };
  if (subject.runs.size() > 1) {
    spec["encoding"]["xOffset"] = {{"field", "run"}, {"type", "nominal"}};
    spec["encoding"]["color"]["legend"] = json::object({{"title", "run"}});
  }
  return spec;
}

}  // namespace kessler::server::figures
