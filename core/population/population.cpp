#include "core/population/population.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <unordered_set>

#include "core/physics/constants.hpp"

namespace kessler {

void StateArrays::resize(std::size_t n) {
  for (auto* v : {&x, &y, &z, &vx, &vy, &vz}) v->resize(n);
}

void StateArrays::set(std::size_t i, const Eigen::Vector3d& r, const Eigen::Vector3d& v) {
  x[i] = r.x();
  y[i] = r.y();
  z[i] = r.z();
  vx[i] = v.x();
  vy[i] = v.y();
  vz[i] = v.z();
}

void Population::reserve(std::size_t n) {
  id.reserve(n);
  name.reserve(n);
  for (auto* v : {&state.x, &state.y, &state.z, &state.vx, &state.vy, &state.vz, &radius_m, &mass_kg,
                  &drag_area_to_mass_m2_kg, &srp_area_to_mass_m2_kg})
    v->reserve(n);
  status.reserve(n);
  type.reserve(n);
  separation_group.reserve(n);
}

void Population::add(const ObjectRecord& r) {
  id.push_back(r.id);
  name.push_back(r.name);
  state.x.push_back(r.position_m.x());
  state.y.push_back(r.position_m.y());
  state.z.push_back(r.position_m.z());
  state.vx.push_back(r.velocity_m_s.x());
  state.vy.push_back(r.velocity_m_s.y());
  state.vz.push_back(r.velocity_m_s.z());
  radius_m.push_back(r.radius_m);
  mass_kg.push_back(r.mass_kg);
  drag_area_to_mass_m2_kg.push_back(r.drag_area_to_mass_m2_kg);
  srp_area_to_mass_m2_kg.push_back(r.srp_area_to_mass_m2_kg);
  status.push_back(r.status);
  type.push_back(r.type);
  separation_group.push_back(r.separation_group);
}

void Population::append_default(std::size_t n) {
  const std::size_t m = size() + n;
  id.resize(m, 0);
  name.resize(m);
  state.resize(m);
  for (auto* v : {&radius_m, &mass_kg, &drag_area_to_mass_m2_kg, &srp_area_to_mass_m2_kg}) v->resize(m, 0.0);
  status.resize(m, ObjectStatus::kPassive);
  type.resize(m, ObjectType::kUnknown);
  separation_group.resize(m, 0);
}

ObjectRecord Population::record(std::size_t i) const {
  ObjectRecord r;
  r.id = id[i];
  r.name = name[i];
  r.position_m = state.position(i);
  r.velocity_m_s = state.velocity(i);
  r.radius_m = radius_m[i];
  r.mass_kg = mass_kg[i];
  r.drag_area_to_mass_m2_kg = drag_area_to_mass_m2_kg[i];
  r.srp_area_to_mass_m2_kg = srp_area_to_mass_m2_kg[i];
  r.status = status[i];
  r.type = type[i];
  r.separation_group = separation_group[i];
  return r;
}

namespace {
// Closes the gaps left by the removed indices (ascending), moving the runs between them down: nothing
// before the first removed index moves, and plain columns move by memmove. A step burns up a handful
// of objects, so this costs a few runs per column, not a test per object (the serial remainder of a
// step with burn-ups, while the team waits).
template <typename T>
void compact(std::vector<T>& v, const std::vector<std::size_t>& removed) {
  std::size_t out = removed.front();
  for (std::size_t k = 0; k < removed.size(); ++k) {
    const std::size_t from = removed[k] + 1, to = k + 1 < removed.size() ? removed[k + 1] : v.size();
    std::move(v.begin() + static_cast<std::ptrdiff_t>(from), v.begin() + static_cast<std::ptrdiff_t>(to),
              v.begin() + static_cast<std::ptrdiff_t>(out));
    out += to - from;
  }
  v.resize(out);
}
}  // namespace

void Population::remove_flagged(const std::vector<char>& flags) {
  std::vector<std::size_t> removed;
  for_each_flagged(flags.data(), 0, size(), [&](std::size_t i) { removed.push_back(i); });
  if (removed.empty()) return;
  compact(id, removed);
  compact(name, removed);
  for (auto* v : {&state.x, &state.y, &state.z, &state.vx, &state.vy, &state.vz, &radius_m, &mass_kg,
                  &drag_area_to_mass_m2_kg, &srp_area_to_mass_m2_kg})
    compact(*v, removed);
  compact(status, removed);
  compact(type, removed);
  compact(separation_group, removed);
}

std::optional<std::size_t> Population::index_of(ObjectId object_id) const {
  for (std::size_t i = 0; i < id.size(); ++i)
    if (id[i] == object_id) return i;
  return std::nullopt;
}

// The largest object radius taken: the biggest structure in orbit spans about 110 m.
constexpr double kMaxObjectRadius_m = 1000.0;

std::optional<std::string> validate_record(const ObjectRecord& r) {
  auto problem = [&](const char* field, const std::string& reason) {
    std::ostringstream s;
    s << "object " << r.id;
    if (!r.name.empty()) s << " (" << r.name << ")";
    s << ": " << field << " " << reason;
    return std::optional<std::string>(s.str());
  };
  if (!r.position_m.allFinite()) return problem("position", "is not finite");
  if (!r.velocity_m_s.allFinite()) return problem("velocity", "is not finite");
  if (r.position_m.norm() < constants::kEarthEquatorialRadius_m - 30000.0)  // below the polar surface
    return problem("position", "is below the Earth's surface");
  // Bound orbits only: an object at escape speed or above leaves the simulated domain.
  const double energy_j_kg =
      0.5 * r.velocity_m_s.squaredNorm() - constants::kEarthMu_m3_s2 / r.position_m.norm();
  if (!(energy_j_kg < 0.0)) return problem("velocity", "is at or above escape speed (not a bound orbit)");
  if (!std::isfinite(r.radius_m) || r.radius_m <= 0.0) return problem("radius_m", "must be positive");
  if (r.radius_m > kMaxObjectRadius_m) return problem("radius_m", "must be at most 1000 m");
  if (!std::isfinite(r.mass_kg) || r.mass_kg <= 0.0) return problem("mass_kg", "must be positive");
  if (!std::isfinite(r.drag_area_to_mass_m2_kg) || r.drag_area_to_mass_m2_kg < 0.0)
    return problem("drag_area_to_mass_m2_kg", "must be finite and non-negative");
  if (!std::isfinite(r.srp_area_to_mass_m2_kg) || r.srp_area_to_mass_m2_kg < 0.0)
    return problem("srp_area_to_mass_m2_kg", "must be finite and non-negative");
  return std::nullopt;
}

std::optional<std::string> Population::validate() const {
  std::unordered_set<ObjectId> seen;
  seen.reserve(size());
  for (std::size_t i = 0; i < size(); ++i) {
    if (auto problem = validate_record(record(i))) return problem;
    if (!seen.insert(id[i]).second) return "object " + std::to_string(id[i]) + ": id is not unique";
  }
  return std::nullopt;
}

}  // namespace kessler
