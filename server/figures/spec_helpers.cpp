// What every figure shares: the spec's head and the time axis.
#include <algorithm>

#include "server/figures/figure.hpp"
#include "server/store.hpp"

namespace kessler::server::figures {

TimeAxis time_axis_for(double longest_run_s) {
  constexpr double kDay = 86400.0;
  constexpr double kYear = 365.25 * kDay;
  if (longest_run_s > 2 * kYear) return {kYear, "simulated time [years]"};
  if (longest_run_s < 2 * kDay) return {3600.0, "simulated time [hours]"};
  return {kDay, "simulated time [days]"};
}

double run_length_s(const v1::RunStats& stats) {
  return static_cast<double>(stats.bin_start_s_size()) * stats.time_bin_s();
}

double run_reached_s(const RunData& data) {
  if (is_terminal(data.run.state()))
    return data.run.has_summary() ? data.run.summary().sim_time_s() : run_length_s(data.stats);
  return data.run.has_progress() ? data.run.progress().sim_time_s() : 0.0;
}

nlohmann::json base_spec(const std::string& title, const std::string& subtitle) {
  nlohmann::json spec = {
      {"$schema", "https://vega.github.io/schema/vega-lite/v5.json"},
      {"width", 640},
      {"height", 300},
      {"config", {{"font", "sans-serif"}, {"axis", {{"labelFontSize", 12}, {"titleFontSize", 13}}}}},
  };
  spec["title"] = {{"text", title}};
  if (!subtitle.empty()) spec["title"]["subtitle"] = subtitle;
  return spec;
}

}  // namespace kessler::server::figures
