// Figure 3: the sizes of the two objects in each conjunction, and the size distribution of objects in
// conjunctions against the population's (the LADDS paper's Fig. 5).
#include <algorithm>
#include <map>
#include <unordered_map>

#include "server/figures/figure_support.hpp"
#include "server/figures/snapshot_figures.hpp"

namespace kessler::server {

using namespace figures;

namespace {

bool is_conjunction(const v1::Encounter& e) {
  return e.kind() != v1::ENCOUNTER_KIND_EVASION;
}

// Radius bins for both panels: 4 per decade from 1 mm to 100 m.
Bins radius_bins() {
  return log_bins(-3, 2, 4);
}

nlohmann::json pair_density_panel(const std::map<std::pair<std::size_t, std::size_t>, std::uint64_t>& cells,
                                  const Bins& bins) {
  nlohmann::json values = nlohmann::json::array();
  for (const auto& [key, n] : cells)
    values.push_back({{"larger_start", bins.edges[key.first]},
                      {"larger_end", bins.edges[key.first + 1]},
                      {"smaller_start", bins.edges[key.second]},
                      {"smaller_end", bins.edges[key.second + 1]},
                      {"conjunctions", n}});
  const nlohmann::json log = {{"type", "log"}};
  return {{"title", "radii of the two objects"},
          {"data", {{"values", values}}},
          {"mark", "rect"},
          {"encoding",
           {{"x",
             {{"field", "larger_start"},
              {"type", "quantitative"},
              {"scale", log},
              {"title", "larger radius [m]"}}},
            {"x2", {{"field", "larger_end"}}},
            {"y",
             {{"field", "smaller_start"},
              {"type", "quantitative"},
              {"scale", log},
              {"title", "smaller radius [m]"}}},
            {"y2", {{"field", "smaller_end"}}},
            {"color", {{"field", "conjunctions"}, {"type", "quantitative"}, {"title", "conjunctions"}}}}}};
}

// Rows {bin_start, bin_end, group, count, fraction} of each group's radius histogram.
void add_histogram(nlohmann::json& values, const std::vector<std::uint64_t>& counts, const Bins& bins,
                   const std::string& group) {
  std::uint64_t total = 0;
  for (std::uint64_t n : counts) total += n;
  for (std::size_t k = 0; k < counts.size(); ++k)
    if (counts[k] > 0)
      values.push_back({{"bin_start", bins.edges[k]},
                        {"bin_end", bins.edges[k + 1]},
                        {"group", group},
                        {"count", counts[k]},
                        {"fraction", static_cast<double>(counts[k]) / static_cast<double>(total)}});
}

}  // namespace

nlohmann::json conjunction_sizes_figure(const std::vector<v1::Encounter>& conjunctions,
                                        const PopulationSnapshot& population) {
  const Bins bins = radius_bins();
  std::unordered_map<ObjectId, float> radius;
  radius.reserve(population.size());
  std::vector<std::uint64_t> population_counts(bins.count(), 0), conjunction_counts(bins.count(), 0);
  for (std::size_t i = 0; i < population.size(); ++i) {
    radius.emplace(population.id[i], population.radius_m[i]);
    ++population_counts[bins.index(population.radius_m[i])];
  }
  std::map<std::pair<std::size_t, std::size_t>, std::uint64_t> cells;
  std::uint64_t used = 0, unmatched = 0;
  for (const v1::Encounter& e : conjunctions) {
    if (!is_conjunction(e)) continue;
    const auto r1 = radius.find(e.id1()), r2 = radius.find(e.id2());
    if (r1 == radius.end() || r2 == radius.end()) {
      ++unmatched;
      continue;
    }
    const double larger = std::max(r1->second, r2->second), smaller = std::min(r1->second, r2->second);
    ++cells[{bins.index(larger), bins.index(smaller)}];
    ++conjunction_counts[bins.index(r1->second)];
    ++conjunction_counts[bins.index(r2->second)];
    ++used;
  }
  if (used == 0) return nullptr;
  nlohmann::json histogram = nlohmann::json::array();
  add_histogram(histogram, population_counts, bins, "population");
  add_histogram(histogram, conjunction_counts, bins, "objects in conjunctions");
  nlohmann::json out =
      spec("Sizes of objects in conjunctions",
           std::to_string(used) + " conjunctions (each object counted once per conjunction); " +
               std::to_string(unmatched) + " with an object not in the population snapshot left out");
  out["hconcat"] = {
      pair_density_panel(cells, bins),
      {{"title", "radius distribution"},
       {"data", {{"values", histogram}}},
       {"mark", {{"type", "line"}, {"interpolate", "step-after"}, {"point", true}}},
       {"encoding",
        {{"x",
          {{"field", "bin_start"},
           {"type", "quantitative"},
           {"scale", {{"type", "log"}}},
           {"title", "radius [m]"}}},
         {"y", {{"field", "fraction"}, {"type", "quantitative"}, {"title", "fraction of objects"}}},
         {"color", {{"field", "group"}, {"type", "nominal"}, {"title", ""}}}}}}};
  return out;
}

}  // namespace kessler::server
