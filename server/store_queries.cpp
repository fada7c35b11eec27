// The store's reads of events: the stream's pages, the latest checkpoint, the conjunction listings and
// the run statistics.
#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

#include "core/simulation/breakups.hpp"
#include "server/store.hpp"
#include "server/store_internal.hpp"

namespace kessler::server {

using namespace detail;

namespace {

// The objects' names, where the run's population has them; a breakup's fragment "FRAGMENT <id>".
void add_names(sqlite3* db, std::int64_t run_id, std::vector<v1::Encounter>& encounters) {
  Statement s(db, "SELECT name FROM object_names WHERE run_id = ? AND object_id = ?");
  std::map<std::uint64_t, std::string> names;
  auto name_of = [&](std::uint64_t id) -> const std::string& {
    auto it = names.find(id);
    if (it != names.end()) return it->second;
    s.reset();
    s.bind(1, run_id).bind(2, id);
    std::string name = s.step() ? s.text(0) : std::string();
    if (name.empty() && id >= kFirstFragmentId) name = "FRAGMENT " + std::to_string(id);  // unnamed
    return names.emplace(id, std::move(name)).first->second;
  };
  for (auto& e : encounters) {
    e.set_name1(name_of(e.id1()));
    e.set_name2(name_of(e.id2()));
  }
}

}  // namespace

// ---- reads ----

std::uint64_t Store::max_seq(std::int64_t run_id) {
  Lease lease(*this);
  Statement s(lease.db(), "SELECT MAX(seq) FROM events WHERE run_id = ?");
  s.bind(1, run_id);
  return s.step() && !s.is_null(0) ? static_cast<std::uint64_t>(s.i64(0)) : 0;
}

std::vector<v1::RunEvent> Store::read_events(std::int64_t run_id, std::uint64_t after_seq, int limit,
                                             bool no_progress) {
  Lease lease(*this);
  Statement s(lease.db(),
              no_progress ? "SELECT payload FROM events WHERE run_id = ? AND seq > ? AND kind != 1 "
                            "ORDER BY seq LIMIT ?"
                          : "SELECT payload FROM events WHERE run_id = ? AND seq > ? ORDER BY seq LIMIT ?");
  s.bind(1, run_id).bind(2, after_seq).bind(3, limit);
  std::vector<v1::RunEvent> events;
  while (s.step()) {
    events.emplace_back();
    if (!events.back().ParseFromString(s.text(0))) throw StoreError("store: corrupt event payload");
  }
  return events;
}

std::optional<StoredCheckpoint> Store::latest_checkpoint(std::int64_t run_id) {
  Lease lease(*this);
  Statement s(lease.db(), "SELECT last_seq, step, bytes FROM checkpoints WHERE run_id = ?");
  s.bind(1, run_id);
  if (!s.step()) return std::nullopt;
  return StoredCheckpoint{static_cast<std::uint64_t>(s.i64(0)), s.i64(1), s.text(2)};
}

Page<v1::Encounter> Store::list_conjunctions(const v1::ListConjunctionsRequest& r) {
  int page_size = r.page_size() <= 0 ? 1000 : std::min(r.page_size(), 100000);
  std::int64_t offset = 0;
  if (!r.page_token().empty()) {
    try {
      offset = std::stoll(r.page_token());
    } catch (...) {
      throw std::invalid_argument("page_token: not a token from a previous page");
    }
  }
  std::string where = "c.run_id = ?1 AND c.kind = 2";
  if (r.has_kappa_min()) where += " AND c.kappa >= ?2";
  if (r.has_kappa_max()) where += " AND c.kappa <= ?3";
  if (r.has_object_id()) where += " AND (c.id1 = ?4 OR c.id2 = ?4)";
  if (r.has_time_min_s()) where += " AND c.tca_s >= ?5";
  if (r.has_time_max_s()) where += " AND c.tca_s <= ?6";
  if (r.collisions_only())
    where += " AND c.encounter_kind = 1";
  else if (!r.include_evasions())
    where += " AND c.encounter_kind != 2";
  // The closest encounter of each pair: SQLite takes the other columns of a MIN() aggregate from the
  // row holding the minimum.
  const std::string columns =
      r.closest_per_pair() ? "c.seq, c.payload, c.tca_s, MIN(c.miss_distance_m) AS miss_distance_m, c.kappa"
                           : "c.seq, c.payload, c.tca_s, c.miss_distance_m, c.kappa";
  std::string selection = "SELECT " + columns + " FROM events c WHERE " + where;
  if (r.closest_per_pair()) selection += " GROUP BY c.id1, c.id2";
  auto bind_all = [&](Statement& s) {
    s.bind(1, r.run_id());
    if (r.has_kappa_min()) s.bind(2, r.kappa_min());
    if (r.has_kappa_max()) s.bind(3, r.kappa_max());
    if (r.has_object_id()) s.bind(4, r.object_id());
    if (r.has_time_min_s()) s.bind(5, r.time_min_s());
    if (r.has_time_max_s()) s.bind(6, r.time_max_s());
  };
  Lease lease(*this);
  Page<v1::Encounter> page;
  {
    Statement count(lease.db(), "SELECT COUNT(*) FROM (" + selection + ")");
    bind_all(count);
    if (count.step()) page.total = static_cast<std::uint64_t>(count.i64(0));
  }
  // order_by is one of the columns RunManager::conjunctions checked, never the caller's text.
  const std::string column = r.order_by().empty() ? "seq" : r.order_by();
  if (column != "seq" && column != "tca_s" && column != "miss_distance_m" && column != "kappa")
    throw std::invalid_argument("order_by: not a column of the listing");
  const std::string direction = r.descending() ? " DESC" : "";
  Statement s(lease.db(), "SELECT seq, payload FROM (" + selection + ") ORDER BY " + column + direction +
                              ", seq" + direction + " LIMIT ?7 OFFSET ?8");
  bind_all(s);
  s.bind(7, page_size + 1).bind(8, offset);
  while (s.step()) {
    v1::RunEvent event;
    if (!event.ParseFromString(s.text(1))) throw StoreError("store: corrupt event payload");
    v1::Encounter encounter = event.encounter();
    encounter.set_seq(static_cast<std::uint64_t>(s.i64(0)));
    page.items.push_back(std::move(encounter));
  }
  if (static_cast<int>(page.items.size()) > page_size) {
    page.items.pop_back();
    page.next_token = std::to_string(offset + page_size);
  }
  add_names(lease.db(), r.run_id(), page.items);
  return page;
}

v1::RunStats Store::run_stats(const v1::GetRunStatsRequest& request, double run_length_s) {
  v1::RunStats stats;
  stats.set_run_id(request.run_id());
  double bin = request.time_bin_s() > 0 ? request.time_bin_s() : std::max(run_length_s, 1.0) / 24.0;
  stats.set_time_bin_s(bin);
  std::size_t bins = static_cast<std::size_t>(std::max(1.0, std::ceil(run_length_s / bin)));
  for (std::size_t i = 0; i < bins; ++i) stats.add_bin_start_s(static_cast<double>(i) * bin);
  std::vector<double> kappas(request.kappas().begin(), request.kappas().end());
  if (kappas.empty()) kappas = {1.0, 2.0, 5.0, 10.0};
  std::sort(kappas.begin(), kappas.end());

  Lease lease(*this);
  {
    Statement counts(lease.db(),
                     "SELECT encounter_kind, COUNT(*) FROM events WHERE run_id = ? AND kind = 2 GROUP BY 1");
    counts.bind(1, request.run_id());
    while (counts.step()) {
      auto n = static_cast<std::uint64_t>(counts.i64(1));
      switch (counts.i64(0)) {
        case 0:
          stats.set_conjunctions(stats.conjunctions() + n);
          break;
        case 1:
          stats.set_collisions(n);
          stats.set_conjunctions(stats.conjunctions() + n);
          break;
        case 2:
          stats.set_evasions(n);
          break;
      }
    }
    Statement burn_ups(lease.db(), "SELECT COUNT(*) FROM events WHERE run_id = ? AND kind = 3");
    burn_ups.bind(1, request.run_id());
    if (burn_ups.step()) stats.set_burn_ups(static_cast<std::uint64_t>(burn_ups.i64(0)));
    Statement breakups(lease.db(),
                       "SELECT COUNT(*), COALESCE(SUM(fragment_count), 0) FROM breakups WHERE run_id = ?");
    breakups.bind(1, request.run_id());
    if (breakups.step()) {
      stats.set_breakups(static_cast<std::uint64_t>(breakups.i64(0)));
      stats.set_fragments(static_cast<std::uint64_t>(breakups.i64(1)));
    }
    count_lifecycle_events(lease.db(), request.run_id(), stats);
  }
  for (double kappa : kappas) {
    v1::KappaSeries* series = stats.add_by_kappa();
    series->set_kappa(kappa);
    std::vector<std::uint64_t> per_bin(bins, 0);
    Statement s(lease.db(),
                "SELECT CAST(tca_s / ? AS INTEGER), COUNT(*) FROM events WHERE run_id = ? AND kind = 2 "
                "AND encounter_kind != 2 AND kappa <= ? GROUP BY 1");
    s.bind(1, bin).bind(2, request.run_id()).bind(3, kappa);
    while (s.step()) {
      std::int64_t b = std::clamp<std::int64_t>(s.i64(0), 0, static_cast<std::int64_t>(bins) - 1);
      per_bin[static_cast<std::size_t>(b)] += static_cast<std::uint64_t>(s.i64(1));
    }
    std::uint64_t total = 0;
    for (std::uint64_t n : per_bin) {
      total += n;
      series->add_per_bin(n);
      series->add_cumulative(total);
    }
  }
  Statement alive(lease.db(), "SELECT payload FROM events WHERE run_id = ? AND kind = 1 ORDER BY seq");
  alive.bind(1, request.run_id());
  while (alive.step()) {
    v1::RunEvent event;
    if (!event.ParseFromString(alive.text(0))) continue;
    v1::AliveSample* sample = stats.add_objects_alive();
    sample->set_sim_time_s(event.progress().sim_time_s());
    sample->set_objects_alive(event.progress().objects_alive());
    *sample->mutable_by_type() = event.progress().objects_by_type();
  }
  return stats;
}

}  // namespace kessler::server
