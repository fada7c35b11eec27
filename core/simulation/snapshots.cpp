#include "core/simulation/snapshots.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

#include "core/physics/constants.hpp"
#include "core/simulation/breakups.hpp"
#include "core/simulation/traffic.hpp"
#include "core/traffic/orbit_elements.hpp"

namespace kessler {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
// Below this eccentricity or sin(inclination) the argument of perigee or the node is undefined.
constexpr double kDegenerate = 1e-11;

double wrap_2pi(double angle_rad) {
  double a = std::fmod(angle_rad, kTwoPi);
  if (a < 0.0) a += kTwoPi;
  return a;
}

// The angle between two vectors in [0, pi], by atan2 (exact near 0 and pi, unlike acos).
double angle_between(const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
  return std::atan2(u.cross(v).norm(), u.dot(v));
}

}  // namespace

OsculatingElements osculating_elements(double x_m, double y_m, double z_m, double vx_m_s, double vy_m_s,
                                       double vz_m_s) {
  const double mu = constants::kEarthMu_m3_s2;
  const Eigen::Vector3d r(x_m, y_m, z_m), v(vx_m_s, vy_m_s, vz_m_s);
  const Eigen::Vector3d h = r.cross(v);
  const Eigen::Vector3d node(-h.y(), h.x(), 0.0);  // z x h: towards the ascending node
  const Eigen::Vector3d e_vec = v.cross(h) / mu - r.normalized();
  OsculatingElements el;
  const double energy = 0.5 * v.squaredNorm() - mu / r.norm();
  el.semi_major_axis_m = -mu / (2.0 * energy);
  el.eccentricity = e_vec.norm();
  el.inclination_rad = std::atan2(std::hypot(h.x(), h.y()), h.z());
  const bool equatorial = node.norm() <= kDegenerate * h.norm();
  const bool circular = el.eccentricity <= kDegenerate;
  const Eigen::Vector3d ref = equatorial ? Eigen::Vector3d::UnitX() : node.normalized();
  el.raan_rad = equatorial ? 0.0 : wrap_2pi(std::atan2(node.y(), node.x()));
  const Eigen::Vector3d h_hat = h.normalized();
  // Angles in the orbit's plane, measured about h from `from` to `to`.
  const auto in_plane = [&](const Eigen::Vector3d& from, const Eigen::Vector3d& to) {
    const double angle = angle_between(from, to);
    return wrap_2pi(from.cross(to).dot(h_hat) >= 0.0 ? angle : -angle);
  };
  el.argument_of_perigee_rad = circular ? 0.0 : in_plane(ref, e_vec);
  const double true_anomaly = circular ? in_plane(ref, r) : in_plane(e_vec, r);
  if (el.eccentricity < 1.0) {
    const double e = el.eccentricity;
    const double ea = std::atan2(std::sqrt(1.0 - e * e) * std::sin(true_anomaly), e + std::cos(true_anomaly));
    el.mean_anomaly_rad = wrap_2pi(ea - e * std::sin(ea));
  }
  return el;
}

void PopulationSnapshot::resize(std::size_t n) {
  id.resize(n);
  type.resize(n);
  status.resize(n);
  for (auto* column : {&radius_m, &mass_kg, &semi_major_axis_m, &eccentricity, &inclination_rad, &raan_rad,
                       &argument_of_perigee_rad, &mean_anomaly_rad})
    column->resize(n);
}

PopulationSnapshot take_snapshot(const Population& p, std::int64_t step, double sim_time_s) {
  PopulationSnapshot s;
  s.step = step;
  s.sim_time_s = sim_time_s;
  const std::size_t n = p.size();
  s.resize(n);
  std::copy(p.id.begin(), p.id.end(), s.id.begin());
  std::copy(p.type.begin(), p.type.end(), s.type.begin());
  std::copy(p.status.begin(), p.status.end(), s.status.begin());
  const auto& st = p.state;
  for (std::size_t i = 0; i < n; ++i) {
    s.radius_m[i] = static_cast<float>(p.radius_m[i]);
    s.mass_kg[i] = static_cast<float>(p.mass_kg[i]);
    const OsculatingElements el =
        osculating_elements(st.x[i], st.y[i], st.z[i], st.vx[i], st.vy[i], st.vz[i]);
    s.semi_major_axis_m[i] = static_cast<float>(el.semi_major_axis_m);
    s.eccentricity[i] = static_cast<float>(el.eccentricity);
    s.inclination_rad[i] = static_cast<float>(el.inclination_rad);
    s.raan_rad[i] = static_cast<float>(el.raan_rad);
    s.argument_of_perigee_rad[i] = static_cast<float>(el.argument_of_perigee_rad);
    s.mean_anomaly_rad[i] = static_cast<float>(el.mean_anomaly_rad);
  }
  return s;
}

ObjectKind kind_of(ObjectId id, ObjectType type) {
  if (id >= kFirstFragmentId && id < kFirstLaunchId) return ObjectKind::kFragment;
  switch (type) {
    case ObjectType::kPayload:
      return ObjectKind::kPayload;
    case ObjectType::kRocketBody:
      return ObjectKind::kRocketBody;
    case ObjectType::kDebris:
      return ObjectKind::kDebris;
    case ObjectType::kUnknown:
      break;
  }
  return ObjectKind::kUnknown;
}

const char* kind_name(ObjectKind kind) {
  switch (kind) {
    case ObjectKind::kPayload:
      return "payload";
    case ObjectKind::kRocketBody:
      return "rocket body";
    case ObjectKind::kDebris:
      return "debris";
    case ObjectKind::kFragment:
      return "fragment";
    case ObjectKind::kUnknown:
      break;
  }
  return "unknown";
}

namespace {

// Samples per orbit, at equal steps of mean anomaly (so equal steps of time).
constexpr int kSamplesPerOrbit = 64;
constexpr double kEarthRadiusKm = constants::kEarthEquatorialRadius_m / 1e3;

double shell_volume_km3(double lower_km, double upper_km) {
  const double r0 = kEarthRadiusKm + lower_km, r1 = kEarthRadiusKm + upper_km;
  return 4.0 / 3.0 * std::numbers::pi * (r1 * r1 * r1 - r0 * r0 * r0);
}

}  // namespace

DensityProfile spatial_density(const PopulationSnapshot& s, double first_altitude_km, double last_altitude_km,
                               double shell_km) {
  DensityProfile p;
  p.shell_km = shell_km;
  p.first_altitude_km = first_altitude_km;
  const auto shells = static_cast<std::size_t>(std::ceil((last_altitude_km - first_altitude_km) / shell_km));
  std::vector<double> objects(shells, 0.0);
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double a_km = s.semi_major_axis_m[i] / 1e3, e = s.eccentricity[i];
    if (!(a_km > 0.0) || !(e < 1.0)) {
      ++p.unbound;
      continue;
    }
    ++p.objects;
    for (int k = 0; k < kSamplesPerOrbit; ++k) {
      const double mean_anomaly = 2.0 * std::numbers::pi * (k + 0.5) / kSamplesPerOrbit;
      const double r_km = a_km * (1.0 - e * std::cos(eccentric_anomaly(mean_anomaly, e)));
      const double shell = std::floor((r_km - kEarthRadiusKm - first_altitude_km) / shell_km);
      // Orbits reaching outside the range count in the outermost shells: the sum stays the count.
      const auto index = static_cast<std::size_t>(std::clamp(shell, 0.0, static_cast<double>(shells - 1)));
      objects[index] += 1.0 / kSamplesPerOrbit;
    }
  }
  p.objects_per_km3.resize(shells);
  for (std::size_t k = 0; k < shells; ++k) {
    const double lower = first_altitude_km + shell_km * static_cast<double>(k);
    p.objects_per_km3[k] = objects[k] / shell_volume_km3(lower, lower + shell_km);
  }
  return p;
}

double DensityProfile::peak_altitude_km() const {
  if (objects_per_km3.empty()) return 0.0;
  const auto peak =
      std::max_element(objects_per_km3.begin(), objects_per_km3.end()) - objects_per_km3.begin();
  return first_altitude_km + shell_km * (static_cast<double>(peak) + 0.5);
}

std::int64_t snapshot_interval_steps(double every_s, double dt_s, std::int64_t total_steps) {
  if (every_s == 0.0 || !(dt_s > 0.0)) return 0;
  if (every_s < 0.0) return std::max<std::int64_t>(1, total_steps / 50);
  return std::max<std::int64_t>(1, std::llround(every_s / dt_s));
}

}  // namespace kessler
