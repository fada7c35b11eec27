// The store's read of one conjunction by its sequence number (for its CDM), with the objects' names.
#include "core/simulation/breakups.hpp"
#include "server/store.hpp"
#include "server/store_internal.hpp"

namespace kessler::server {

using namespace detail;

std::optional<v1::Encounter> Store::conjunction(std::int64_t run_id, std::uint64_t seq) {
  Lease lease(*this);
  Statement s(lease.db(), "SELECT payload FROM events WHERE run_id = ?1 AND seq = ?2 AND kind = 2");
  s.bind(1, run_id).bind(2, seq);
  if (!s.step()) return std::nullopt;
  v1::RunEvent event;
  if (!event.ParseFromString(s.text(0))) throw StoreError("store: corrupt event payload");
  v1::Encounter encounter = event.encounter();
  encounter.set_seq(seq);
  Statement names(lease.db(), "SELECT name FROM object_names WHERE run_id = ? AND object_id = ?");
  auto name_of = [&](std::uint64_t id) {
    names.reset();
    names.bind(1, run_id).bind(2, id);
    std::string name = names.step() ? names.text(0) : std::string();
    if (name.empty() && id >= kFirstFragmentId) name = "FRAGMENT " + std::to_string(id);
    return name;
  };
  encounter.set_name1(name_of(encounter.id1()));
  encounter.set_name2(name_of(encounter.id2()));
  return encounter;
}

}  // namespace kessler::server
