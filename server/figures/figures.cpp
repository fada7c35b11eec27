// The figure registry and the subject loaders; RunManager::figures (the GetFigures RPC) lives here
// too, so the run manager's file stays about runs.
#include "server/figures/figures.hpp"
#include "server/figures/snapshot_figures.hpp"

#include <set>

#include "server/run_manager.hpp"

namespace kessler::server::figures {
namespace {

RunData load_run(RunManager& manager, std::int64_t run_id) {
  RunData data;
  data.run = manager.get(run_id);
  data.run.clear_scenario();
  data.label = "run " + std::to_string(run_id);
  v1::GetRunStatsRequest request;
  request.set_run_id(run_id);
  data.stats = manager.stats(request);
  for (double k : kSweepKappas) request.add_kappas(k);
  data.kappa_sweep = manager.stats(request);
  data.events = manager.store().event_times(run_id);
  return data;
}

}  // namespace

const std::vector<FigureEntry>& registry() {
  static const std::vector<FigureEntry> entries = {
      {"conjunctions-over-time", "Conjunctions over time by kappa", conjunctions_over_time},
      {"conjunctions-vs-kappa", "Conjunctions against kappa", conjunctions_vs_kappa},
      {"runtime-breakdown", "Runtime by phase", runtime_breakdown},
      {"objects-by-type", "Objects on orbit by type", objects_by_type},
  };
  return entries;
}

std::vector<Figure> figures_for(const FigureSubject& subject) {
  std::vector<Figure> out;
  for (const FigureEntry& entry : registry()) {
    nlohmann::json spec = entry.build(subject);
    if (spec.is_null()) continue;
    out.push_back({entry.id, entry.title, std::move(spec), subject.partial});
  }
  return out;
}

FigureSubject load_run_subject(RunManager& manager, std::int64_t run_id,
                               const std::vector<std::int64_t>& compare) {
  using Code = ServiceError::Code;
  if (compare.size() > kMaxCompared)
    throw ServiceError(Code::kInvalidArgument,
                       "compare_run_ids: at most " + std::to_string(kMaxCompared) + " runs",
                       "compare_run_ids");
  FigureSubject subject;
  std::set<std::int64_t> seen;
  seen.insert(run_id);
  subject.runs.push_back(load_run(manager, run_id));
  for (std::int64_t id : compare)
    if (seen.insert(id).second) subject.runs.push_back(load_run(manager, id));
  for (const RunData& r : subject.runs) subject.partial = subject.partial || !is_terminal(r.run.state());
  return subject;
}

FigureSubject load_ensemble_subject(RunManager& manager, std::int64_t ensemble_id) {
  FigureSubject subject;
  v1::GetEnsembleRequest request;
  request.set_ensemble_id(ensemble_id);
  subject.ensemble = manager.get_ensemble(request);
  subject.ensemble->clear_scenario();
  for (const v1::EnsembleMember& m : subject.ensemble->member()) {
    try {
      v1::Run run = manager.get(m.run_id());
      run.clear_scenario();
      subject.ensemble_members.push_back(std::move(run));
    } catch (const ServiceError&) {
      // A member deleted since: the aggregates leave it out too.
    }
  }
  subject.partial = !is_terminal(subject.ensemble->state());
  return subject;
}

std::vector<Figure> figures_for_run(RunManager& manager, std::int64_t run_id,
                                    const std::vector<std::int64_t>& compare) {
  const FigureSubject subject = load_run_subject(manager, run_id, compare);
  std::vector<Figure> out = figures_for(subject);
  // The run's own snapshot- and conjunction-based figures (snapshot_figures.hpp), after the others.
  const nlohmann::json from_snapshots = run_figures(manager, run_id);
  const std::pair<const char*, const char*> kSnapshotFigures[] = {
      {"population_distributions", "population-distributions"},
      {"conjunction_sizes", "conjunction-sizes"},
      {"conjunction_orbits", "conjunction-orbits"},
      {"spatial_density", "spatial-density"},
      {"gabbard", "gabbard"}};
  for (const auto& [key, id] : kSnapshotFigures) {
    const nlohmann::json& spec = from_snapshots.at(key);
    if (spec.is_null()) continue;
    std::string title = id;
    if (spec.contains("title")) {
      const nlohmann::json& t = spec.at("title");
      if (t.is_string()) title = t.get<std::string>();
      if (t.is_object() && t.contains("text") && t.at("text").is_string())
        title = t.at("text").get<std::string>();
    }
    out.push_back(Figure{id, title, spec, subject.partial});
  }
  return out;
}

std::vector<Figure> figures_for_ensemble(RunManager& manager, std::int64_t ensemble_id) {
  return figures_for(load_ensemble_subject(manager, ensemble_id));
}

}  // namespace kessler::server::figures

namespace kessler::server {

v1::GetFiguresResponse RunManager::figures(const v1::GetFiguresRequest& request) {
  std::vector<figures::Figure> list;
  if (request.has_ensemble_id()) {
    if (!request.compare_run_ids().empty())
      throw ServiceError(ServiceError::Code::kInvalidArgument,
                         "compare_run_ids: compares runs, not ensembles", "compare_run_ids");
    list = figures::figures_for_ensemble(*this, request.ensemble_id());
  } else if (request.has_run_id()) {
    list = figures::figures_for_run(*this, request.run_id(),
                                    {request.compare_run_ids().begin(), request.compare_run_ids().end()});
  } else {
    throw ServiceError(ServiceError::Code::kInvalidArgument, "run_id: a run_id or an ensemble_id is required",
                       "run_id");
  }
  v1::GetFiguresResponse response;
  for (const figures::Figure& f : list) {
    v1::Figure* out = response.add_figures();
    out->set_id(f.id);
    out->set_title(f.title);
    out->set_vega_lite_json(f.spec.dump());
    out->set_partial(f.partial);
  }
  return response;
}

}  // namespace kessler::server
