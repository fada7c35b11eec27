// The simulated objects as a structure of arrays: index i is one object in every array, so the
// propagator and the detector stream through contiguous memory and loops vectorise.
//
// Frame and units: positions and velocities are in the TEME frame of the scenario epoch (the inertial
// frame of the whole core), in m and m/s. Ids are stable: removing objects never renumbers the others.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace kessler {

using ObjectId = std::uint64_t;

enum class ObjectStatus : std::uint8_t { kPassive = 0, kActive = 1 };

// What an object is, as the SATCAT says (kUnknown where no SATCAT is given). Breakup fragments are
// kDebris.
enum class ObjectType : std::uint8_t { kUnknown = 0, kPayload = 1, kRocketBody = 2, kDebris = 3 };

// A run's breakups are numbered 1, 2, ... in the order they happen; 0 is none.
using BreakupId = std::uint32_t;

// Positions and velocities of every object, index-aligned with the Population they belong to.
struct StateArrays {
  std::vector<double> x, y, z;     // TEME of epoch [m]
  std::vector<double> vx, vy, vz;  // TEME of epoch [m/s]

  std::size_t size() const { return x.size(); }
  void resize(std::size_t n);
  Eigen::Vector3d position(std::size_t i) const { return {x[i], y[i], z[i]}; }
  Eigen::Vector3d velocity(std::size_t i) const { return {vx[i], vy[i], vz[i]}; }
  void set(std::size_t i, const Eigen::Vector3d& r, const Eigen::Vector3d& v);
};

// One object as a plain record: what catalogs produce and Population::add takes.
struct ObjectRecord {
  ObjectId id = 0;
  std::string name;
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();    // TEME of epoch
  Eigen::Vector3d velocity_m_s = Eigen::Vector3d::Zero();  // TEME of epoch
  double radius_m = 0.0;                                   // collision radius (sphere)
  double mass_kg = 0.0;
  double drag_area_to_mass_m2_kg = 0.0;  // Cd * A / m (ballistic coefficient's inverse)
  double srp_area_to_mass_m2_kg = 0.0;   // A / m facing the Sun (reflectivity 1)
  ObjectStatus status = ObjectStatus::kPassive;
  ObjectType type = ObjectType::kUnknown;
  // Objects with the same non-zero group are not screened against each other: a young breakup's
  // fragments and remnant, while they separate (core/simulation/breakups.hpp). 0: screened against all.
  BreakupId separation_group = 0;
};

class Population {
 public:
  std::vector<ObjectId> id;
  std::vector<std::string> name;
  StateArrays state;
  std::vector<double> radius_m;
  std::vector<double> mass_kg;
  std::vector<double> drag_area_to_mass_m2_kg;
  std::vector<double> srp_area_to_mass_m2_kg;
  std::vector<ObjectStatus> status;
  std::vector<ObjectType> type;
  std::vector<BreakupId> separation_group;  // ObjectRecord::separation_group

  std::size_t size() const { return id.size(); }
  bool empty() const { return id.empty(); }
  void reserve(std::size_t n);

  // Appends one object. Does not validate: call validate_record first where input is untrusted.
  void add(const ObjectRecord& record);
  // Appends n objects with default columns (empty names, passive, kUnknown, group 0, zero state): the
  // caller then fills indices [size() - n, size()) column by column (bulk insertion of fragments).
  void append_default(std::size_t n);
  ObjectRecord record(std::size_t i) const;

  // Removes the objects whose flag is 1 (flags.size() == size(); each flag 0 or 1), keeping the order of
  // the rest.
  void remove_flagged(const std::vector<char>& flags);

  // Index of an id, if present (linear scan; for tests and tools, not hot loops).
  std::optional<std::size_t> index_of(ObjectId object_id) const;

  // First problem found, as "object <id> (<name>): <field> <reason>", or nullopt when every object
  // is sound: finite states above the Earth's surface, positive radius and mass, non-negative areas,
  // unique ids.
  std::optional<std::string> validate() const;
};

// The problem with one record, or nullopt: the same rules as Population::validate.
std::optional<std::string> validate_record(const ObjectRecord& record);

// Calls f(i) for each i in [begin, end) whose per-object flag is 1, in order. Flags set are rare (burn-ups,
// low objects, far-out boxes), so it jumps from one to the next with memchr.
template <class F>
void for_each_flagged(const char* flags, std::size_t begin, std::size_t end, F&& f) {
  for (const char* p = flags + begin; p < flags + end; ++p) {
    p = static_cast<const char*>(std::memchr(p, 1, static_cast<std::size_t>(flags + end - p)));
    if (p == nullptr) return;
    f(static_cast<std::size_t>(p - flags));
  }
}

}  // namespace kessler
