// What the figures share: the spec's frame, bins, and an object's orbit quantities.
#pragma once

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/physics/constants.hpp"
#include "core/simulation/snapshots.hpp"

namespace kessler::server::figures {

inline constexpr double kEarthRadiusKm = constants::kEarthEquatorialRadius_m / 1e3;
inline constexpr double kDegPerRad = 57.29577951308232;

// A Vega-Lite v5 spec with a title and a description (what the figure shows and what was left out).
inline nlohmann::json spec(const std::string& title, const std::string& description) {
  return {{"$schema", "https://vega.github.io/schema/vega-lite/v5.json"},
          {"title", title},
          {"description", description}};
}

// Bins [edges[k], edges[k + 1]); values outside the edges go to the first or last bin.
struct Bins {
  std::vector<double> edges;
  std::size_t index(double v) const {
    if (!(v >= edges.front())) return 0;
    for (std::size_t k = 1; k + 1 < edges.size(); ++k)
      if (v < edges[k]) return k - 1;
    return edges.size() - 2;
  }
  std::size_t count() const { return edges.size() - 1; }
};

// Equal bins in log10 from 10^lo to 10^hi, `per_decade` per decade.
inline Bins log_bins(int lo, int hi, int per_decade) {
  Bins b;
  for (int k = 0; k <= (hi - lo) * per_decade; ++k)
    b.edges.push_back(std::pow(10.0, lo + static_cast<double>(k) / per_decade));
  return b;
}

inline Bins linear_bins(double lo, double hi, double width) {
  Bins b;
  for (double x = lo; x <= hi + 1e-9; x += width) b.edges.push_back(x);
  return b;
}

inline double altitude_km(double semi_major_axis_m) {
  return semi_major_axis_m / 1e3 - kEarthRadiusKm;
}

// "t = 12 d", "t = 1.5 d", or hours under a day ("t = 0.24 h"): what labels an epoch of a run.
inline std::string time_label(double sim_time_s) {
  const double days = sim_time_s / 86400.0;
  char text[48];
  if (days >= 10.0)
    std::snprintf(text, sizeof text, "t = %.0f d", days);
  else if (days >= 1.0)
    std::snprintf(text, sizeof text, "t = %.1f d", days);
  else
    std::snprintf(text, sizeof text, "t = %.2f h", sim_time_s / 3600.0);
  return text;
}

inline const char* status_name(ObjectStatus s) {
  return s == ObjectStatus::kActive ? "active" : "passive";
}

}  // namespace kessler::server::figures
