#include "server/ensembles.hpp"

#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>
#include <string>

#include "server/run_manager.hpp"

namespace kessler::server {
namespace {

using Code = ServiceError::Code;

double unix_now_s() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

double mean(const std::vector<double>& values) {
  if (values.empty()) return 0.0;
  double sum = 0.0;
  for (double v : values) sum += v;
  return sum / static_cast<double>(values.size());
}

// Events at or before t in ascending times.
double count_until(const std::vector<double>& times, double t) {
  return static_cast<double>(std::upper_bound(times.begin(), times.end(), t) - times.begin());
}

// The sample at `t` over the members, `at[m]` the index of t in member m's samples.
v1::EnsembleSample sample_at(const std::vector<MemberResults>& members, const std::vector<std::size_t>& at,
                             double t) {
  const std::size_t n = members.size();
  const std::size_t kappas = members.front().conjunction_times.size();
  std::vector<double> objects(n), payload(n), rocket(n), debris(n), unknown(n), fragments(n);
  std::vector<double> collisions(n), catastrophic(n);
  std::vector<std::vector<double>> conjunctions(kappas, std::vector<double>(n));
  for (std::size_t m = 0; m < n; ++m) {
    const v1::AliveSample& s = members[m].alive[at[m]];
    objects[m] = static_cast<double>(s.objects_alive());
    payload[m] = static_cast<double>(s.by_type().payload());
    rocket[m] = static_cast<double>(s.by_type().rocket_body());
    debris[m] = static_cast<double>(s.by_type().debris());
    unknown[m] = static_cast<double>(s.by_type().unknown());
    fragments[m] = static_cast<double>(s.by_type().fragments());
    collisions[m] = count_until(members[m].collision_times, t);
    catastrophic[m] = count_until(members[m].catastrophic_times, t);
    for (std::size_t k = 0; k < kappas; ++k)
      conjunctions[k][m] = count_until(members[m].conjunction_times[k], t);
  }
  v1::EnsembleSample out;
  out.set_t(t);
  out.set_objects_mean(mean(objects));
  std::sort(objects.begin(), objects.end());
  out.set_objects_median(percentile(objects, 0.5));
  out.set_objects_p05(percentile(objects, 0.05));
  out.set_objects_p95(percentile(objects, 0.95));
  out.set_payload_mean(mean(payload));
  out.set_rocket_body_mean(mean(rocket));
  out.set_debris_mean(mean(debris));
  out.set_unknown_mean(mean(unknown));
  out.set_fragments_mean(mean(fragments));
  out.set_collisions_mean(mean(collisions));
  out.set_catastrophic_mean(mean(catastrophic));
  for (auto& c : conjunctions) {
    out.add_conjunctions_mean(mean(c));
    std::sort(c.begin(), c.end());
    out.add_conjunctions_p05(percentile(c, 0.05));
    out.add_conjunctions_p95(percentile(c, 0.95));
  }
  return out;
}

v1::EnsembleMember member_of(const v1::Run& run, const StoredEnsemble& e) {
  v1::EnsembleMember m;
  m.set_run_id(run.id());
  m.set_member_index(run.member_index());
  m.set_seed(e.base_seed + run.member_index());
  m.set_state(run.state());
  if (run.has_summary()) m.set_events_digest(run.summary().events_digest());
  return m;
}

}  // namespace

double percentile(const std::vector<double>& sorted, double p) {
  if (sorted.empty()) return 0.0;
  const double h = static_cast<double>(sorted.size() - 1) * std::clamp(p, 0.0, 1.0);
  const auto lo = static_cast<std::size_t>(std::floor(h));
  if (lo + 1 >= sorted.size()) return sorted.back();
  return sorted[lo] + (h - static_cast<double>(lo)) * (sorted[lo + 1] - sorted[lo]);
}

std::vector<double> common_times(const std::vector<MemberResults>& members) {
  if (members.empty()) return {};
  std::vector<double> common;
  for (const auto& s : members.front().alive) common.push_back(s.sim_time_s());
  std::sort(common.begin(), common.end());
  common.erase(std::unique(common.begin(), common.end()), common.end());
  for (std::size_t m = 1; m < members.size(); ++m) {
    std::set<double> have;
    for (const auto& s : members[m].alive) have.insert(s.sim_time_s());
    std::erase_if(common, [&](double t) { return !have.count(t); });
  }
  return common;
}

std::vector<v1::EnsembleSample> aggregate_series(const std::vector<MemberResults>& members) {
  std::vector<v1::EnsembleSample> series;
  const std::vector<double> times = common_times(members);
  std::vector<std::size_t> at(members.size(), 0);
  for (double t : times) {
    // Each member's samples ascend in time: walk them forward to t.
    for (std::size_t m = 0; m < members.size(); ++m) {
      const auto& alive = members[m].alive;
      while (at[m] < alive.size() && alive[at[m]].sim_time_s() != t) ++at[m];
      if (at[m] == alive.size()) throw std::logic_error("ensemble: a member's progress times do not ascend");
    }
    series.push_back(sample_at(members, at, t));
  }
  return series;
}

v1::RunState ensemble_state(const std::map<v1::RunState, std::uint64_t>& counts) {
  auto count = [&](v1::RunState s) {
    auto it = counts.find(s);
    return it == counts.end() ? std::uint64_t{0} : it->second;
  };
  const std::uint64_t queued = count(v1::RUN_STATE_QUEUED), running = count(v1::RUN_STATE_RUNNING);
  const std::uint64_t ended =
      count(v1::RUN_STATE_SUCCEEDED) + count(v1::RUN_STATE_FAILED) + count(v1::RUN_STATE_CANCELLED);
  if (running > 0 || (queued > 0 && ended > 0)) return v1::RUN_STATE_RUNNING;
  if (queued > 0) return v1::RUN_STATE_QUEUED;
  if (count(v1::RUN_STATE_FAILED) > 0) return v1::RUN_STATE_FAILED;
  if (count(v1::RUN_STATE_CANCELLED) > 0) return v1::RUN_STATE_CANCELLED;
  return v1::RUN_STATE_SUCCEEDED;
}

// ---- the RunManager's ensemble calls ----

v1::EnsembleReport RunManager::submit_ensemble(const v1::SubmitEnsembleRequest& request,
                                               const std::string& submitter) {
  const std::string& request_id = request.request_id();
  if (!request_id.empty())
    if (auto id = store_.ensemble_of_request(submitter, request_id)) return get_ensemble_members(*id);
  const v1::Scenario scenario =
      read_scenario(request.has_scenario() ? &request.scenario() : nullptr,
                    request.has_scenario_text() ? &request.scenario_text() : nullptr);
  const std::uint64_t members = request.members() > 0 ? request.members() : scenario.ensemble().members();
  if (members < 1 || members > options_.max_ensemble_members)
    throw ServiceError(Code::kInvalidArgument,
                       "ensemble.members: must be in 1.." + std::to_string(options_.max_ensemble_members) +
                           ", got " + std::to_string(members),
                       "ensemble.members");
  v1::Scenario base = scenario;
  base.clear_ensemble();
  const std::uint64_t seed = base.has_seed() ? base.seed() : 1;  // the core's default seed
  if (seed > std::numeric_limits<std::uint64_t>::max() - (members - 1))
    throw ServiceError(Code::kInvalidArgument, "seed: seed + members - 1 must fit in 64 bits", "seed");
  std::optional<v1::IngestReport> ingest = admit(base, request.threads());
  if (ingest) malloc_trim(0);  // the ingest's buffers go back to the system
  if (scheduler_->queued() + members > options_.queue_limit)
    throw ServiceError(Code::kResourceExhausted, "queue full: " + std::to_string(scheduler_->queued()) +
                                                     " of " + std::to_string(options_.queue_limit) +
                                                     " runs are waiting, the ensemble needs " +
                                                     std::to_string(members) + " more; try later");
  std::vector<v1::Scenario> member_scenarios(members, base);
  for (std::uint64_t k = 0; k < members; ++k) member_scenarios[k].set_seed(seed + k);
  const int threads = request.threads() > 0 ? request.threads() : options_.threads_per_run;
  v1::Scenario submitted = scenario;
  submitted.mutable_ensemble()->set_members(members);
  std::unique_lock same_request(requests_mutex_, std::defer_lock);
  if (!request_id.empty()) {
    same_request.lock();  // a retry racing its first try finds the first ensemble here
    if (auto existing = store_.ensemble_of_request(submitter, request_id))
      return get_ensemble_members(*existing);
  }
  auto [id, runs] =
      store_.create_ensemble(submitted, member_scenarios, threads, seed, unix_now_s(), submitter, request_id);
  for (std::int64_t run_id : runs) {
    if (ingest) store_.set_ingest(run_id, *ingest);
    scheduler_->enqueue(run_id, true);  // the room was checked above
  }
  return get_ensemble_members(id);
}

v1::EnsembleReport RunManager::get_ensemble_members(std::int64_t ensemble_id) {
  v1::EnsembleReport report = ensemble_head(ensemble_id);
  auto e = store_.get_ensemble(ensemble_id, false);
  if (!e) throw ServiceError(Code::kNotFound, "ensemble " + std::to_string(ensemble_id) + " not found");
  for (const v1::Run& run : store_.ensemble_runs(ensemble_id)) *report.add_member() = member_of(run, *e);
  return report;
}

v1::EnsembleReport RunManager::ensemble_head(std::int64_t ensemble_id) {
  auto e = store_.get_ensemble(ensemble_id, false);
  if (!e) throw ServiceError(Code::kNotFound, "ensemble " + std::to_string(ensemble_id) + " not found");
  const auto counts = store_.ensemble_states(ensemble_id);
  v1::EnsembleReport report;
  report.set_id(e->id);
  report.set_name(e->name);
  report.set_created_unix_s(e->created_unix_s);
  report.set_base_seed(e->base_seed);
  report.set_members(e->members);
  report.set_submitter(e->submitter);
  report.set_state(ensemble_state(counts));
  std::uint64_t finished = 0;
  for (const auto& [state, n] : counts)
    if (is_terminal(state)) finished += n;
  report.set_finished(finished);
  auto succeeded = counts.find(v1::RUN_STATE_SUCCEEDED);
  report.set_aggregated(succeeded == counts.end() ? 0 : succeeded->second);
  return report;
}

v1::EnsembleReport RunManager::get_ensemble(const v1::GetEnsembleRequest& request) {
  v1::EnsembleReport report = ensemble_head(request.ensemble_id());
  auto e = store_.get_ensemble(request.ensemble_id(), true);
  if (!e)
    throw ServiceError(Code::kNotFound, "ensemble " + std::to_string(request.ensemble_id()) + " not found");
  std::vector<double> kappas(request.kappas().begin(), request.kappas().end());
  for (double k : kappas)
    if (!(k > 0)) throw ServiceError(Code::kInvalidArgument, "kappas: must be > 0", "kappas");
  if (kappas.empty()) kappas = {1.0, 2.0, 5.0, 10.0};
  std::sort(kappas.begin(), kappas.end());
  for (double k : kappas) report.add_kappas(k);
  *report.mutable_scenario() = e->scenario;
  strip_inline_data(*report.mutable_scenario());  // GetRun with include_inline_data returns them
  std::vector<MemberResults> results;
  for (const v1::Run& run : store_.ensemble_runs(e->id)) {
    *report.add_member() = member_of(run, *e);
    if (run.state() == v1::RUN_STATE_SUCCEEDED) results.push_back(store_.member_results(run.id(), kappas));
  }
  // The counts and the results come from separate reads: aggregated is what the series covers.
  report.set_aggregated(results.size());
  for (auto& sample : aggregate_series(results)) *report.add_series() = std::move(sample);
  return report;
}

v1::ListEnsemblesResponse RunManager::list_ensembles(const v1::ListEnsemblesRequest& request,
                                                     const std::string* submitter) {
  if (request.page_size() < 0)
    throw ServiceError(Code::kInvalidArgument, "page_size: must be >= 0", "page_size");
  Page<StoredEnsemble> page;
  try {
    page = store_.list_ensembles(request.page_size(), request.page_token(), submitter);
  } catch (const std::invalid_argument& e) {
    throw ServiceError(Code::kInvalidArgument, e.what(), "page_token");
  }
  v1::ListEnsemblesResponse response;
  for (const StoredEnsemble& e : page.items) *response.add_ensembles() = ensemble_head(e.id);
  response.set_next_page_token(page.next_token);
  return response;
}

v1::EnsembleReport RunManager::cancel_ensemble(std::int64_t ensemble_id) {
  v1::EnsembleReport head = ensemble_head(ensemble_id);  // NOT_FOUND
  if (is_terminal(head.state()))
    throw ServiceError(Code::kFailedPrecondition, "ensemble " + std::to_string(ensemble_id) +
                                                      " has already ended (" + run_state_name(head.state()) +
                                                      ")");
  for (const v1::Run& run : store_.ensemble_runs(ensemble_id)) {
    if (is_terminal(run.state())) continue;
    try {
      cancel(run.id());
    } catch (const ServiceError& e) {
      if (e.code != Code::kFailedPrecondition) throw;  // it ended meanwhile
    }
  }
  return get_ensemble_members(ensemble_id);
}

}  // namespace kessler::server
