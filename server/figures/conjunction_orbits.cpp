// Figure 4: semi-major axis and inclination of the objects in conjunctions against the population's
// (the LADDS paper's Fig. 6).
#include "server/figures/figure_support.hpp"
#include "server/figures/snapshot_figures.hpp"

namespace kessler::server {

using namespace figures;

namespace {

struct Histograms {
  Bins altitude = linear_bins(0, 2500, 50);
  Bins inclination = linear_bins(0, 180, 5);
  std::vector<std::uint64_t> population_altitude, population_inclination, conjunction_altitude,
      conjunction_inclination;
  Histograms()
      : population_altitude(altitude.count()),
        population_inclination(inclination.count()),
        conjunction_altitude(altitude.count()),
        conjunction_inclination(inclination.count()) {}
};

void add_fractions(nlohmann::json& values, const std::vector<std::uint64_t>& counts, const Bins& bins,
                   const std::string& quantity, const std::string& group) {
  std::uint64_t total = 0;
  for (std::uint64_t n : counts) total += n;
  for (std::size_t k = 0; k < counts.size(); ++k)
    values.push_back(
        {{"quantity", quantity},
         {"bin_start", bins.edges[k]},
         {"bin_end", bins.edges[k + 1]},
         {"group", group},
         {"count", counts[k]},
         {"fraction", total ? static_cast<double>(counts[k]) / static_cast<double>(total) : 0.0}});
}

nlohmann::json panel(const nlohmann::json& values, const std::string& quantity, const std::string& x_title) {
  return {{"data", {{"values", values}}},
          {"transform", {{{"filter", {{"field", "quantity"}, {"equal", quantity}}}}}},
          {"mark", {{"type", "line"}, {"interpolate", "step-after"}}},
          {"encoding",
           {{"x", {{"field", "bin_start"}, {"type", "quantitative"}, {"title", x_title}}},
            {"y", {{"field", "fraction"}, {"type", "quantitative"}, {"title", "fraction of objects"}}},
            {"color", {{"field", "group"}, {"type", "nominal"}, {"title", ""}}}}}};
}

}  // namespace

nlohmann::json conjunction_orbits_figure(const std::vector<v1::Encounter>& conjunctions,
                                         const PopulationSnapshot& population) {
  Histograms h;
  for (std::size_t i = 0; i < population.size(); ++i) {
    ++h.population_altitude[h.altitude.index(altitude_km(population.semi_major_axis_m[i]))];
    ++h.population_inclination[h.inclination.index(population.inclination_rad[i] * kDegPerRad)];
  }
  std::uint64_t used = 0;
  for (const v1::Encounter& e : conjunctions) {
    if (e.kind() == v1::ENCOUNTER_KIND_EVASION) continue;
    for (const auto* rv : {&e.r1_m(), &e.r2_m()}) {
      const v1::Vector3& v = rv == &e.r1_m() ? e.v1_m_s() : e.v2_m_s();
      const OsculatingElements el = osculating_elements(rv->x(), rv->y(), rv->z(), v.x(), v.y(), v.z());
      ++h.conjunction_altitude[h.altitude.index(altitude_km(el.semi_major_axis_m))];
      ++h.conjunction_inclination[h.inclination.index(el.inclination_rad * kDegPerRad)];
    }
    ++used;
  }
  if (used == 0) return nullptr;
  nlohmann::json values = nlohmann::json::array();
  add_fractions(values, h.population_altitude, h.altitude, "altitude", "population");
  add_fractions(values, h.conjunction_altitude, h.altitude, "altitude", "objects in conjunctions");
  add_fractions(values, h.population_inclination, h.inclination, "inclination", "population");
  add_fractions(values, h.conjunction_inclination, h.inclination, "inclination", "objects in conjunctions");
  nlohmann::json out =
      spec("Orbits of objects in conjunctions", std::to_string(used) +
                                                    " conjunctions; objects' osculating elements at closest "
                                                    "approach against the population snapshot's at step " +
                                                    std::to_string(population.step));
  out["hconcat"] = {panel(values, "altitude", "semi-major axis altitude [km]"),
                    panel(values, "inclination", "inclination [deg]")};
  return out;
}

}  // namespace kessler::server
