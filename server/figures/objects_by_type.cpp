// Figure 6: objects on orbit over time by type (the catalog's payloads, rocket bodies, debris, and the
// fragments of the run's breakups), with launches, re-entries and breakups marked, gathered into the
// run's time bins so a long run stays readable. An ensemble: the members' means by type, and the 5-95 %
// band of the total.
#include <algorithm>
#include <map>

#include "server/figures/figure.hpp"

namespace kessler::server::figures {
namespace {

using nlohmann::json;

const char* const kTypeOrder[] = {"all objects", "payload", "rocket body",
                                  "debris",      "unknown", "breakup fragments"};

void add_type_rows(json& rows, const std::string& run, double t, double all, const v1::ObjectCounts& c,
                   bool with_unknown) {
  rows.push_back({{"run", run}, {"type", "all objects"}, {"t", t}, {"n", all}});
  rows.push_back({{"run", run}, {"type", "payload"}, {"t", t}, {"n", c.payload()}});
  rows.push_back({{"run", run}, {"type", "rocket body"}, {"t", t}, {"n", c.rocket_body()}});
  rows.push_back({{"run", run}, {"type", "debris"}, {"t", t}, {"n", c.debris()}});
  if (with_unknown) rows.push_back({{"run", run}, {"type", "unknown"}, {"t", t}, {"n", c.unknown()}});
  rows.push_back({{"run", run}, {"type", "breakup fragments"}, {"t", t}, {"n", c.fragments()}});
}

// One marker per kind and time bin that holds any: at the bin's middle, with the count.
void add_event_marks(json& marks, const RunData& data, const TimeAxis& axis) {
  const double bin = data.stats.time_bin_s() > 0 ? data.stats.time_bin_s() : 1.0;
  auto add = [&](const char* kind, const std::vector<std::pair<double, std::uint64_t>>& times) {
    std::map<long, std::uint64_t> per_bin;
    for (const auto& [t, n] : times) per_bin[static_cast<long>(t / bin)] += n;
    for (const auto& [b, n] : per_bin)
      marks.push_back({{"run", data.label},
                       {"event", kind},
                       {"t", (static_cast<double>(b) + 0.5) * bin / axis.seconds_per_unit},
                       {"count", n}});
  };
  auto ones = [](const std::vector<double>& times) {
    std::vector<std::pair<double, std::uint64_t>> out;
    out.reserve(times.size());
    for (double t : times) out.emplace_back(t, 1);
    return out;
  };
  add("launches (objects)", data.events.launches);
  std::vector<double> reentries = data.events.burn_ups_s;
  reentries.insert(reentries.end(), data.events.deorbits_s.begin(), data.events.deorbits_s.end());
  add("re-entries", ones(reentries));
  add("breakups", ones(data.events.breakups_s));
}

json type_sort() {
  json order = json::array();
  for (const char* t : kTypeOrder) order.push_back(t);
  return order;
}

json lines_layer(const TimeAxis& axis, bool by_run) {
  json layer = {
      {"mark", "line"},
      {"encoding",
       {{"x", {{"field", "t"}, {"type", "quantitative"}, {"title", axis.title}}},
        {"y", {{"field", "n"}, {"type", "quantitative"}, {"title", "objects on orbit"}}},
        {"color", {{"field", "type"}, {"type", "nominal"}, {"sort", type_sort()}, {"title", "type"}}},
        {"tooltip", json::array({{{"field", "run"}},
                                 {{"field", "type"}},
                                 {{"field", "t"}, {"title", axis.title}},
                                 {{"field", "n"}, {"title", "objects"}}})}}}};
  if (by_run) layer["encoding"]["strokeDash"] = {{"field", "run"}, {"type", "nominal"}};
  return layer;
}

json ensemble_spec(const v1::EnsembleReport& report) {
  if (report.series_size() == 0) return nullptr;
  const TimeAxis axis = time_axis_for(report.series(report.series_size() - 1).t());
  json rows = json::array();
  json band = json::array();
  bool unknown = false;
  for (const auto& s : report.series()) unknown = unknown || s.unknown_mean() > 0;
  for (const auto& s : report.series()) {
    const double t = s.t() / axis.seconds_per_unit;
    rows.push_back({{"run", "mean"}, {"type", "all objects"}, {"t", t}, {"n", s.objects_mean()}});
    rows.push_back({{"run", "mean"}, {"type", "payload"}, {"t", t}, {"n", s.payload_mean()}});
    rows.push_back({{"run", "mean"}, {"type", "rocket body"}, {"t", t}, {"n", s.rocket_body_mean()}});
    rows.push_back({{"run", "mean"}, {"type", "debris"}, {"t", t}, {"n", s.debris_mean()}});
    if (unknown) rows.push_back({{"run", "mean"}, {"type", "unknown"}, {"t", t}, {"n", s.unknown_mean()}});
    rows.push_back({{"run", "mean"}, {"type", "breakup fragments"}, {"t", t}, {"n", s.fragments_mean()}});
    band.push_back({{"t", t}, {"p05", s.objects_p05()}, {"p95", s.objects_p95()}});
  }
  json spec = base_spec("Objects on orbit by type", "means over " + std::to_string(report.aggregated()) +
                                                        " members; band: 5-95 % of all objects");
  json area = {{"data", {{"values", band}}},
               {"mark", {{"type", "area"}, {"opacity", 0.25}, {"color", "#4c78a8"}}},
               {"encoding",
                {{"x", {{"field", "t"}, {"type", "quantitative"}, {"title", axis.title}}},
                 {"y", {{"field", "p05"}, {"type", "quantitative"}}},
                 {"y2", {{"field", "p95"}}}}}};
  json lines = lines_layer(axis, false);
  lines["data"] = {{"values", rows}};
  spec["layer"] = json::array({area, lines});
  return spec;
}

}  // namespace

json objects_by_type(const FigureSubject& subject) {
  if (subject.ensemble) return ensemble_spec(*subject.ensemble);
  double longest = 0;
  for (const RunData& r : subject.runs) longest = std::max(longest, run_length_s(r.stats));
  const TimeAxis axis = time_axis_for(longest);
  json rows = json::array();
  json marks = json::array();
  for (const RunData& r : subject.runs) {
    bool unknown = false;
    for (const auto& a : r.stats.objects_alive()) unknown = unknown || a.by_type().unknown() > 0;
    for (const auto& a : r.stats.objects_alive())
      add_type_rows(rows, r.label, a.sim_time_s() / axis.seconds_per_unit,
                    static_cast<double>(a.objects_alive()), a.by_type(), unknown);
    add_event_marks(marks, r, axis);
  }
  if (rows.empty()) return nullptr;
  json spec =
      base_spec("Objects on orbit by type", "markers: launches, re-entries and breakups per time bin");
  json lines = lines_layer(axis, subject.runs.size() > 1);
  lines["data"] = {{"values", rows}};
  json layers = json::array({lines});
  if (!marks.empty()) {
    layers.push_back(
        {{"data", {{"values", marks}}},
         {"mark", {{"type", "rule"}, {"strokeWidth", 2}, {"opacity", 0.6}}},
         {"encoding",
          {{"x", {{"field", "t"}, {"type", "quantitative"}}},
           {"strokeDash", {{"field", "event"}, {"type", "nominal"}, {"title", "events (per bin)"}}},
           {"tooltip", json::array({{{"field", "run"}}, {{"field", "event"}}, {{"field", "count"}}})}}}});
  }
  spec["layer"] = layers;
  return spec;
}

}  // namespace kessler::server::figures
