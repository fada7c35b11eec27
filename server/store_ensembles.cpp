// The store's ensembles: the ensembles table, their member runs (runs.ensemble_id, member_index), and
// what the aggregates read of a member's results.
#include <algorithm>
#include <stdexcept>

#include "server/store.hpp"
#include "server/store_internal.hpp"

namespace kessler::server {

using namespace detail;

namespace {

const char* const kEnsembleColumns = "id, name, created_unix_s, members, base_seed, submitter";

StoredEnsemble ensemble_from_row(const Statement& s) {
  StoredEnsemble e;
  e.id = s.i64(0);
  e.name = s.text(1);
  e.created_unix_s = s.f64(2);
  e.members = static_cast<std::uint64_t>(s.i64(3));
  e.base_seed = static_cast<std::uint64_t>(s.i64(4));
  e.submitter = s.text(5);
  return e;
}

}  // namespace

std::pair<std::int64_t, std::vector<std::int64_t>> Store::create_ensemble(
    const v1::Scenario& submitted, const std::vector<v1::Scenario>& members, int threads,
    std::uint64_t base_seed, double created_unix_s, const std::string& submitter,
    const std::string& request_id) {
  Lease lease(*this);
  exec(lease.db(), "BEGIN IMMEDIATE");
  try {
    Statement s(
        lease.db(),
        "INSERT INTO ensembles(name, scenario, members, base_seed, created_unix_s, submitter, request_id) "
        "VALUES(?, ?, ?, ?, ?, ?, ?)");
    const std::string bytes = submitted.SerializeAsString();
    s.bind(1, submitted.name()).bind_blob(2, bytes).bind(3, static_cast<std::uint64_t>(members.size()));
    s.bind(4, base_seed).bind(5, created_unix_s).bind(6, submitter);
    if (request_id.empty())
      s.bind_null(7);
    else
      s.bind(7, request_id);
    s.run();
    const std::int64_t id = sqlite3_last_insert_rowid(lease.db());
    std::vector<std::int64_t> runs;
    runs.reserve(members.size());
    for (std::size_t k = 0; k < members.size(); ++k)
      runs.push_back(insert_run(lease.db(), members[k], threads, created_unix_s, id, k, submitter, ""));
    exec(lease.db(), "COMMIT");
    return {id, runs};
  } catch (...) {
    sqlite3_exec(lease.db(), "ROLLBACK", nullptr, nullptr, nullptr);
    throw;
  }
}

std::optional<StoredEnsemble> Store::get_ensemble(std::int64_t ensemble_id, bool with_scenario) {
  Lease lease(*this);
  Statement s(lease.db(),
              std::string("SELECT ") + kEnsembleColumns + ", scenario FROM ensembles WHERE id = ?");
  s.bind(1, ensemble_id);
  if (!s.step()) return std::nullopt;
  StoredEnsemble e = ensemble_from_row(s);
  if (with_scenario) e.scenario.ParseFromString(s.text(6));
  return e;
}

Page<StoredEnsemble> Store::list_ensembles(int page_size, const std::string& page_token,
                                           const std::string* submitter) {
  page_size = page_size <= 0 ? 50 : std::min(page_size, 1000);
  std::int64_t before = INT64_MAX;
  if (!page_token.empty()) {
    std::size_t used = 0;
    try {
      before = std::stoll(page_token, &used);
    } catch (...) {
      used = 0;
    }
    if (used != page_token.size())
      throw std::invalid_argument("page_token: not a token from a previous page");
  }
  Lease lease(*this);
  Statement s(lease.db(), std::string("SELECT ") + kEnsembleColumns + " FROM ensembles WHERE id < ?" +
                              (submitter ? " AND submitter = ?3" : "") + " ORDER BY id DESC LIMIT ?2");
  s.bind(1, before).bind(2, page_size + 1);
  if (submitter) s.bind(3, *submitter);
  Page<StoredEnsemble> page;
  while (s.step()) page.items.push_back(ensemble_from_row(s));
  if (static_cast<int>(page.items.size()) > page_size) {
    page.items.pop_back();
    page.next_token = std::to_string(page.items.back().id);
  }
  return page;
}

std::vector<v1::Run> Store::ensemble_runs(std::int64_t ensemble_id) {
  Lease lease(*this);
  Statement s(lease.db(), std::string("SELECT ") + kRunColumnsSql +
                              " FROM runs WHERE ensemble_id = ? ORDER BY member_index");
  s.bind(1, ensemble_id);
  std::vector<v1::Run> runs;
  while (s.step()) runs.push_back(run_row(s));
  return runs;
}

std::map<v1::RunState, std::uint64_t> Store::ensemble_states(std::int64_t ensemble_id) {
  Lease lease(*this);
  Statement s(lease.db(), "SELECT state, COUNT(*) FROM runs WHERE ensemble_id = ? GROUP BY state");
  s.bind(1, ensemble_id);
  std::map<v1::RunState, std::uint64_t> counts;
  while (s.step()) counts[static_cast<v1::RunState>(s.i64(0))] = static_cast<std::uint64_t>(s.i64(1));
  return counts;
}

MemberResults Store::member_results(std::int64_t run_id, const std::vector<double>& kappas) {
  MemberResults out;
  out.conjunction_times.resize(kappas.size());
  Lease lease(*this);
  {
    Statement s(lease.db(), "SELECT payload FROM events WHERE run_id = ? AND kind = ? ORDER BY seq");
    s.bind(1, run_id).bind(2, static_cast<int>(kKindProgress));
    while (s.step()) {
      v1::RunEvent event;
      if (!event.ParseFromString(s.text(0))) throw StoreError("store: corrupt event payload");
      v1::AliveSample sample;
      sample.set_sim_time_s(event.progress().sim_time_s());
      sample.set_objects_alive(event.progress().objects_alive());
      *sample.mutable_by_type() = event.progress().objects_by_type();
      // One sample per time: a later event at the same time replaces an earlier one.
      if (!out.alive.empty() && out.alive.back().sim_time_s() == sample.sim_time_s())
        out.alive.back() = std::move(sample);
      else
        out.alive.push_back(std::move(sample));
    }
  }
  {
    Statement s(lease.db(),
                "SELECT tca_s, kappa, encounter_kind FROM events WHERE run_id = ? AND kind = ? AND "
                "encounter_kind != 2");
    s.bind(1, run_id).bind(2, static_cast<int>(kKindEncounter));
    while (s.step()) {
      const double t = s.f64(0), kappa = s.f64(1);
      if (s.i64(2) == 1) out.collision_times.push_back(t);
      for (std::size_t i = 0; i < kappas.size(); ++i)
        if (kappa <= kappas[i]) out.conjunction_times[i].push_back(t);
    }
  }
  {
    Statement s(lease.db(),
                "SELECT time_s FROM breakups WHERE run_id = ? AND source = ? AND catastrophic = 1");
    s.bind(1, run_id).bind(2, static_cast<int>(v1::BREAKUP_SOURCE_COLLISION));
    while (s.step()) out.catastrophic_times.push_back(s.f64(0));
  }
  std::sort(out.collision_times.begin(), out.collision_times.end());
  std::sort(out.catastrophic_times.begin(), out.catastrophic_times.end());
  for (auto& times : out.conjunction_times) std::sort(times.begin(), times.end());
  return out;
}

}  // namespace kessler::server
