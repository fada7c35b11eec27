// The figures of one run, read through the run manager (the service layer's read path).
#include <algorithm>

#include "server/figures/snapshot_figures.hpp"
#include "server/run_manager.hpp"

namespace kessler::server {

namespace {

constexpr std::size_t kGabbardEpochs = 4;

std::vector<v1::Encounter> all_conjunctions(RunManager& m, std::int64_t run_id) {
  std::vector<v1::Encounter> out;
  v1::ListConjunctionsRequest r;
  r.set_run_id(run_id);
  r.set_page_size(100000);
  do {
    v1::ListConjunctionsResponse page = m.conjunctions(r);
    for (auto& c : *page.mutable_conjunctions()) out.push_back(std::move(c));
    r.set_page_token(page.next_page_token());
  } while (!r.page_token().empty());
  return out;
}

std::vector<v1::Fragment> all_fragments(RunManager& m, std::int64_t run_id) {
  std::vector<v1::Fragment> out;
  v1::ListFragmentsRequest r;
  r.set_run_id(run_id);
  r.set_page_size(100000);
  do {
    v1::ListFragmentsResponse page = m.fragments(r);
    for (auto& f : *page.mutable_fragments()) out.push_back(std::move(f));
    r.set_page_token(page.next_page_token());
  } while (!r.page_token().empty());
  return out;
}

// Up to kGabbardEpochs snapshots after the first, evenly spread, that hold fragments.
std::vector<PopulationSnapshot> gabbard_epochs(RunManager& m, std::int64_t run_id,
                                               const std::vector<StoredSnapshotInfo>& rows,
                                               const std::vector<v1::Fragment>& fragments) {
  std::vector<PopulationSnapshot> out;
  if (fragments.empty() || rows.size() < 2) return out;
  const std::size_t later = rows.size() - 1;
  const std::size_t picks = std::min(kGabbardEpochs, later);
  for (std::size_t k = 1; k <= picks; ++k) {
    const std::size_t index = 1 + (later - 1) * k / picks;
    auto s = m.population_snapshot(run_id, rows[index].step);
    if (!s) continue;
    const bool has_fragments = std::any_of(s->id.begin(), s->id.end(), [&](ObjectId id) {
      return id >= fragments.front().id() && id <= fragments.back().id();
    });
    if (has_fragments) out.push_back(std::move(*s));
  }
  return out;
}

}  // namespace

nlohmann::json run_figures(RunManager& m, std::int64_t run_id) {
  nlohmann::json out = nlohmann::json::object();
  const std::vector<StoredSnapshotInfo> rows = m.snapshot_steps(run_id);  // NOT_FOUND first
  const std::vector<v1::Encounter> conjunctions = all_conjunctions(m, run_id);
  if (rows.empty()) {
    for (const char* name : {"population_distributions", "conjunction_sizes", "conjunction_orbits",
                             "spatial_density", "gabbard"})
      out[name] = nullptr;
    return out;
  }
  const PopulationSnapshot first = *m.population_snapshot(run_id, rows.front().step);
  const PopulationSnapshot last = *m.population_snapshot(run_id, rows.back().step);
  out["population_distributions"] = population_distributions_figure(first);
  out["conjunction_sizes"] = conjunction_sizes_figure(conjunctions, first);
  out["conjunction_orbits"] = conjunction_orbits_figure(conjunctions, first);
  out["spatial_density"] = spatial_density_figure(first, last);
  const std::vector<v1::Fragment> fragments = all_fragments(m, run_id);
  out["gabbard"] = gabbard_figure(fragments, gabbard_epochs(m, run_id, rows, fragments));
  return out;
}

}  // namespace kessler::server
