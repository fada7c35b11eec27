// The store's population snapshots: written by the writer thread (encoded there, off the simulation's
// and the relay's threads), read by step.
#include <algorithm>
#include <stdexcept>

#include "server/snapshot_codec.hpp"
#include "server/store.hpp"
#include "server/store_internal.hpp"

namespace kessler::server {

using namespace detail;

// A resumed run hands over again the snapshots after its checkpoint: the first copy stays.
const char* const detail::kSnapshotInsertSql =
    "INSERT OR IGNORE INTO snapshots(run_id, step, sim_time_s, objects, bytes) VALUES(?, ?, ?, ?, ?)";

void detail::write_snapshot_row(Statement& snapshot_insert, std::int64_t run_id,
                                const PopulationSnapshot& snapshot) {
  const std::string bytes = encode_snapshot(snapshot);
  snapshot_insert.bind(1, run_id).bind(2, snapshot.step).bind(3, snapshot.sim_time_s);
  snapshot_insert.bind(4, static_cast<std::uint64_t>(snapshot.size())).bind_blob(5, bytes);
  snapshot_insert.run();
}

void Store::append_snapshot(std::int64_t run_id, std::shared_ptr<const PopulationSnapshot> snapshot) {
  Pending p;
  p.run_id = run_id;
  p.snapshot = std::move(snapshot);
  enqueue(std::move(p));
}

Page<StoredSnapshotInfo> Store::list_snapshots(std::int64_t run_id, int page_size,
                                               const std::string& page_token) {
  page_size = page_size <= 0 ? 1000 : std::min(page_size, 100000);
  std::int64_t after = -1;
  if (!page_token.empty()) {
    std::size_t used = 0;
    try {
      after = std::stoll(page_token, &used);
    } catch (...) {
      used = 0;
    }
    if (used != page_token.size() || after < 0)
      throw std::invalid_argument("page_token: not a token from a previous page");
  }
  Lease lease(*this);
  Page<StoredSnapshotInfo> page;
  {
    Statement count(lease.db(), "SELECT COUNT(*) FROM snapshots WHERE run_id = ?");
    count.bind(1, run_id);
    if (count.step()) page.total = static_cast<std::uint64_t>(count.i64(0));
  }
  Statement s(lease.db(),
              "SELECT step, sim_time_s, objects, LENGTH(bytes) FROM snapshots WHERE run_id = ? AND step > ? "
              "ORDER BY step LIMIT ?");
  s.bind(1, run_id).bind(2, after).bind(3, page_size + 1);
  while (s.step()) {
    if (page.items.size() == static_cast<std::size_t>(page_size)) {
      page.next_token = std::to_string(page.items.back().step);
      break;
    }
    page.items.push_back(
        {s.i64(0), s.f64(1), static_cast<std::uint64_t>(s.i64(2)), static_cast<std::uint64_t>(s.i64(3))});
  }
  return page;
}

namespace {

// The row of the last snapshot at or before `step` (the newest when nullopt); `columns` selected.
std::string snapshot_query(const char* columns, bool bounded) {
  return std::string("SELECT ") + columns + " FROM snapshots WHERE run_id = ?1" +
         (bounded ? " AND step <= ?2" : "") + " ORDER BY step DESC LIMIT 1";
}

}  // namespace

std::optional<PopulationSnapshot> Store::read_snapshot(std::int64_t run_id,
                                                       std::optional<std::int64_t> step) {
  Lease lease(*this);
  Statement s(lease.db(), snapshot_query("bytes", step.has_value()));
  s.bind(1, run_id);
  if (step) s.bind(2, *step);
  if (!s.step()) return std::nullopt;
  try {
    return decode_snapshot(s.text(0));
  } catch (const std::runtime_error& e) {
    throw StoreError(std::string("store: ") + e.what());
  }
}

std::optional<StoredSnapshotInfo> Store::snapshot_info(std::int64_t run_id,
                                                       std::optional<std::int64_t> step) {
  Lease lease(*this);
  Statement s(lease.db(), snapshot_query("step, sim_time_s, objects, LENGTH(bytes)", step.has_value()));
  s.bind(1, run_id);
  if (step) s.bind(2, *step);
  if (!s.step()) return std::nullopt;
  return StoredSnapshotInfo{s.i64(0), s.f64(1), static_cast<std::uint64_t>(s.i64(2)),
                            static_cast<std::uint64_t>(s.i64(3))};
}

}  // namespace kessler::server
