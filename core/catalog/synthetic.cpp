#include "core/catalog/synthetic.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "core/physics/constants.hpp"
#include "core/random/counter_random.hpp"

namespace kessler {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Histograms of the real catalog (catalog-2022, paper's LEO filter, SGP4 mean elements), from
//   /usr/bin/python3 (stdlib + python3-sgp4) over deploy/datasets/catalog: counts per 100 km of
//   semi-major-axis altitude (a - 6378.135 km), from 100 km up ...
constexpr double kAltitudeCounts[] = {5,   68,  247, 1522, 1795, 1720, 2903, 3080, 1888, 840,
                                      487, 459, 290, 908,  410,  143,  17,   6,    3};
constexpr double kAltitudeFirstBinKm = 100.0;
// ... per 10 degrees of inclination from 0 ...
constexpr double kInclinationCounts[] = {17,   15,   115,  189, 177, 313, 1066, 2494,
                                         3783, 7601, 1002, 4,   3,   0,   12};
// ... eccentricity mean 0.0093 (median 0.0046): exponential; and RCS classes (small, medium, large)
// of objects with a class: active 99/275/457, passive 9704/1722/1754.
constexpr double kMeanEccentricity = 0.0093;
constexpr double kActiveClasses[] = {99, 275, 457};
constexpr double kPassiveClasses[] = {9704, 1722, 1754};

// Index drawn from weights with uniform u in (0, 1).
template <std::size_t N>
std::size_t draw_bin(const double (&weights)[N], double u, std::size_t first = 0, std::size_t last = N) {
  double total = 0.0;
  for (std::size_t i = first; i < last; ++i) total += weights[i];
  double target = u * total;
  for (std::size_t i = first; i < last; ++i) {
    if (target < weights[i]) return i;
    target -= weights[i];
  }
  return last - 1;
}

}  // namespace

Population generate_synthetic(const SyntheticOptions& o, std::uint64_t seed) {
  if (!(o.min_altitude_km < o.max_altitude_km) || o.min_altitude_km < 100.0 || o.max_altitude_km > 40000.0)
    throw std::invalid_argument("synthetic population: altitude band " + std::to_string(o.min_altitude_km) +
                                ".." + std::to_string(o.max_altitude_km) +
                                " km must be increasing within 100..40000 km");
  if (!(o.active_fraction >= 0.0 && o.active_fraction <= 1.0))
    throw std::invalid_argument("synthetic population: active_fraction must lie in 0..1");

  const std::size_t n = o.objects;
  Population p;
  p.id.resize(n);
  p.name.resize(n);
  p.state.resize(n);
  p.radius_m.resize(n);
  p.mass_kg.resize(n);
  p.drag_area_to_mass_m2_kg.resize(n);
  p.srp_area_to_mass_m2_kg.resize(n);
  p.status.resize(n);
  p.type.resize(n, ObjectType::kUnknown);
  p.separation_group.resize(n, 0);

  // Altitude bins overlapping the band.
  constexpr std::size_t kBins = sizeof kAltitudeCounts / sizeof kAltitudeCounts[0];
  double weights[kBins];
  for (std::size_t b = 0; b < kBins; ++b) {
    const double lo = kAltitudeFirstBinKm + 100.0 * b, hi = lo + 100.0;
    const double overlap = std::max(0.0, std::min(hi, o.max_altitude_km) - std::max(lo, o.min_altitude_km));
    weights[b] = kAltitudeCounts[b] * overlap / 100.0;
  }
  bool any = false;
  for (double w : weights) any = any || w > 0.0;
  const double re_km = constants::kEarthEquatorialRadius_m / 1000.0;
  const double mu = constants::kEarthMu_m3_s2;

#pragma omp parallel for schedule(static)
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint64_t id = o.first_id + k;
    auto u = [&](std::uint64_t c) { return random_uniform(seed, id, RandomPurpose::kSyntheticOrbit, c); };
    // Semi-major-axis altitude: histogram bin, uniform inside, clipped to the band.
    double alt_km;
    if (any) {
      const std::size_t b = draw_bin(weights, u(0));
      const double lo = std::max(kAltitudeFirstBinKm + 100.0 * b, o.min_altitude_km);
      const double hi = std::min(kAltitudeFirstBinKm + 100.0 * (b + 1), o.max_altitude_km);
      alt_km = lo + (hi - lo) * u(1);
    } else {
      alt_km = o.min_altitude_km + (o.max_altitude_km - o.min_altitude_km) * u(1);
    }
    const double a = (re_km + alt_km) * 1000.0;
    // Eccentricity: exponential, capped so that the perigee stays above the band's lower edge.
    const double e_cap = std::max(0.0, 1.0 - (re_km + o.min_altitude_km) * 1000.0 / a);
    const double e = std::min(-kMeanEccentricity * std::log(u(2)), e_cap);
    const std::size_t ib = draw_bin(kInclinationCounts, u(3));
    const double inc = (10.0 * ib + 10.0 * u(4)) * kPi / 180.0;
    const double raan = 2.0 * kPi * u(5), argp = 2.0 * kPi * u(6), mean_anomaly = 2.0 * kPi * u(7);

    // Kepler: eccentric anomaly by Newton, then the perifocal state rotated to the inertial frame.
    double ea = mean_anomaly;
    for (int it = 0; it < 20; ++it) ea -= (ea - e * std::sin(ea) - mean_anomaly) / (1.0 - e * std::cos(ea));
    const double cos_e = std::cos(ea), sin_e = std::sin(ea);
    const double b = a * std::sqrt(1.0 - e * e);
    const double r = a * (1.0 - e * cos_e);
    const double px = a * (cos_e - e), py = b * sin_e;
    const double vfac = std::sqrt(mu * a) / r;
    const double pvx = -vfac * sin_e, pvy = vfac * std::sqrt(1.0 - e * e) * cos_e;
    const double co = std::cos(raan), so = std::sin(raan), cw = std::cos(argp), sw = std::sin(argp);
    const double ci = std::cos(inc), si = std::sin(inc);
    const double r11 = co * cw - so * sw * ci, r12 = -co * sw - so * cw * ci;
    const double r21 = so * cw + co * sw * ci, r22 = -so * sw + co * cw * ci;
    const double r31 = sw * si, r32 = cw * si;
    p.state.x[k] = r11 * px + r12 * py;
    p.state.y[k] = r21 * px + r22 * py;
    p.state.z[k] = r31 * px + r32 * py;
    p.state.vx[k] = r11 * pvx + r12 * pvy;
    p.state.vy[k] = r21 * pvx + r22 * pvy;
    p.state.vz[k] = r31 * pvx + r32 * pvy;

    // Status, size class, radius, mass and areas.
    const bool active = random_uniform(seed, id, RandomPurpose::kSyntheticStatus, 0) < o.active_fraction;
    const double uc = random_uniform(seed, id, RandomPurpose::kSyntheticSize, 0);
    const std::size_t c = active ? draw_bin(kActiveClasses, uc) : draw_bin(kPassiveClasses, uc);
    const RcsSizeClass size_class = c == 0   ? RcsSizeClass::kSmall
                                    : c == 1 ? RcsSizeClass::kMedium
                                             : RcsSizeClass::kLarge;
    const double radius = sample_radius_m(o.sizes, size_class, seed, id);
    const double mass = mass_from_radius_kg(radius);
    p.id[k] = id;
    p.name[k] = "SYNTHETIC " + std::to_string(id);
    p.radius_m[k] = radius;
    p.mass_kg[k] = mass;
    p.drag_area_to_mass_m2_kg[k] = drag_area_to_mass_from_size(radius, mass, o.drag_coefficient);
    p.srp_area_to_mass_m2_kg[k] = srp_area_to_mass(radius, mass);
    p.status[k] = active ? ObjectStatus::kActive : ObjectStatus::kPassive;
  }
  return p;
}

}  // namespace kessler
