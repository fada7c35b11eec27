// The store's breakups and lifecycle events: the writer's rows of a breakup and its fragments, and of a
// lifecycle event; the fragment listing.
#include <algorithm>
#include <stdexcept>
#include <string>

#include "server/store.hpp"
#include "server/store_internal.hpp"

namespace kessler::server {

using namespace detail;

namespace detail {

const char* const kBreakupInsertSql =
    "INSERT OR IGNORE INTO breakups(run_id, breakup_id, seq, time_s, kind, source, catastrophic, "
    "fragment_count, first_id, last_id, remnant_id) VALUES(?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)";
const char* const kFragmentInsertSql =
    "INSERT OR IGNORE INTO fragments(run_id, fragment_id, breakup_id, parent_id, characteristic_length_m, "
    "area_to_mass_m2_kg, mass_kg, delta_v_m_s) VALUES(?, ?, ?, ?, ?, ?, ?, ?)";

void write_breakup_rows(Statement& breakup_insert, Statement& fragment_insert, const v1::RunEvent& event,
                        const std::vector<StoredFragment>& fragments) {
  const v1::Breakup& b = event.breakup();
  const auto breakup_id = static_cast<std::int64_t>(b.breakup_id());
  breakup_insert.bind(1, event.run_id()).bind(2, breakup_id).bind(3, event.seq()).bind(4, b.time_s());
  breakup_insert.bind(5, static_cast<int>(b.kind())).bind(6, static_cast<int>(b.source()));
  breakup_insert.bind(7, b.catastrophic() ? 1 : 0).bind(8, b.fragment_count()).bind(9, b.first_id());
  breakup_insert.bind(10, b.last_id()).bind(11, b.remnant_id());
  breakup_insert.run();
  for (const StoredFragment& f : fragments) {
    fragment_insert.bind(1, event.run_id()).bind(2, f.id).bind(3, breakup_id).bind(4, f.parent_id);
    fragment_insert.bind(5, f.characteristic_length_m).bind(6, f.area_to_mass_m2_kg).bind(7, f.mass_kg);
    fragment_insert.bind(8, f.delta_v_m_s);
    fragment_insert.run();
  }
}

const char* const kLifecycleInsertSql =
    "INSERT OR IGNORE INTO lifecycle_events(run_id, seq, kind, time_s, first_id, last_id, plan_row, "
    "altitude_m) VALUES(?, ?, ?, ?, ?, ?, ?, ?)";

void write_lifecycle_row(Statement& lifecycle_insert, const v1::RunEvent& event) {
  const v1::Lifecycle& l = event.lifecycle();
  lifecycle_insert.bind(1, event.run_id()).bind(2, event.seq()).bind(3, static_cast<int>(l.kind()));
  lifecycle_insert.bind(4, l.time_s()).bind(5, l.first_id()).bind(6, l.last_id()).bind(7, l.row());
  lifecycle_insert.bind(8, l.altitude_m());
  lifecycle_insert.run();
}

void count_lifecycle_events(sqlite3* db, std::int64_t run_id, v1::RunStats& stats) {
  Statement s(db,
              "SELECT kind, COUNT(*), COALESCE(SUM(last_id - first_id + 1), 0) FROM lifecycle_events "
              "WHERE run_id = ? GROUP BY 1");
  s.bind(1, run_id);
  while (s.step()) {
    const auto n = static_cast<std::uint64_t>(s.i64(1));
    switch (s.i64(0)) {
      case v1::LIFECYCLE_KIND_LAUNCH:
        stats.set_launches(n);
        stats.set_launched_objects(static_cast<std::uint64_t>(s.i64(2)));
        break;
      case v1::LIFECYCLE_KIND_END_OF_LIFE:
        stats.set_ends_of_life(n);
        break;
      case v1::LIFECYCLE_KIND_DISPOSAL:
        stats.set_disposals(n);
        break;
      case v1::LIFECYCLE_KIND_DISPOSAL_FAILED:
        stats.set_disposals_failed(n);
        break;
      case v1::LIFECYCLE_KIND_DEORBIT:
        stats.set_deorbits(n);
        break;
    }
  }
}

}  // namespace detail

Page<v1::Fragment> Store::list_fragments(const v1::ListFragmentsRequest& r) {
  const int page_size = r.page_size() <= 0 ? 1000 : std::min(r.page_size(), 100000);
  std::int64_t offset = 0;
  if (!r.page_token().empty()) {
    std::size_t used = 0;
    try {
      offset = std::stoll(r.page_token(), &used);
    } catch (...) {
      used = 0;
    }
    if (used != r.page_token().size() || offset < 0)
      throw std::invalid_argument("page_token: not a token from a previous page");
  }
  const std::string where = r.has_breakup_id() ? "run_id = ?1 AND breakup_id = ?2" : "run_id = ?1";
  auto bind_all = [&](Statement& s) {
    s.bind(1, r.run_id());
    if (r.has_breakup_id()) s.bind(2, static_cast<std::int64_t>(r.breakup_id()));
  };
  Lease lease(*this);
  Page<v1::Fragment> page;
  {
    Statement count(lease.db(), "SELECT COUNT(*) FROM fragments WHERE " + where);
    bind_all(count);
    if (count.step()) page.total = static_cast<std::uint64_t>(count.i64(0));
  }
  Statement s(
      lease.db(),
      "SELECT fragment_id, breakup_id, parent_id, characteristic_length_m, area_to_mass_m2_kg, mass_kg, "
      "delta_v_m_s FROM fragments WHERE " +
          where + " ORDER BY fragment_id LIMIT ?3 OFFSET ?4");
  bind_all(s);
  s.bind(3, page_size + 1).bind(4, offset);
  while (s.step()) {
    v1::Fragment f;
    f.set_id(static_cast<std::uint64_t>(s.i64(0)));
    f.set_breakup_id(static_cast<std::uint32_t>(s.i64(1)));
    f.set_parent_id(static_cast<std::uint64_t>(s.i64(2)));
    f.set_characteristic_length_m(s.f64(3));
    f.set_area_to_mass_m2_kg(s.f64(4));
    f.set_mass_kg(s.f64(5));
    f.set_delta_v_m_s(s.f64(6));
    page.items.push_back(std::move(f));
  }
  if (static_cast<int>(page.items.size()) > page_size) {
    page.items.pop_back();
    page.next_token = std::to_string(offset + page_size);
  }
  return page;
}

}  // namespace kessler::server
