// The ballistic-coefficient fit (core/decay/): each observed decay rate against the theory it comes from
// (SGP4's own propagation, Kepler's third law), the orbit-averaged drag against King-Hele's circular-orbit
// formula, and the fit against the numerical propagator: an object whose element set reports the decay the
// propagator gives some Cd A/m gets that Cd A/m back.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/catalog/tle.hpp"
#include "core/decay/ballistic_fit.hpp"
#include "core/decay/run_atmosphere.hpp"
#include "core/integration/symplectic_propagator.hpp"
#include "core/physics/atmosphere.hpp"
#include "core/physics/constants.hpp"

namespace kessler {
namespace {

constexpr double kMu = constants::kEarthMu_m3_s2;
constexpr double kRe = constants::kEarthEquatorialRadius_m;

MeanElements elements_of(const std::string& tle) {
  const ElementSetText parsed = parse_tle_text(tle, {}, "test");
  EXPECT_EQ(parsed.sets.size(), 1u);
  return parsed.sets.front().elements;
}

// ISS, 2022-01-22 (the bundled catalog).
const char* const kIss =
    "1 25544U 98067A   22022.91470718  .00005958  00000-0  11386-3 0  9994\n"
    "2 25544  51.6445 336.0056 0006830  51.7508  17.5213 15.49594026322655\n";
// A Thor-Agena D fragment at 760 km, 2019-03-19 (the bundled 2019 catalog).
const char* const kThoradDebris =
    "1  4820U 70025EB  19078.59674092 +.00002249 +00000-0 +85384-3 0  9993\n"
    "2  4820 099.6979 038.8220 0028105 318.5096 041.3950 14.32017760463495\n";

double osculating_a(const Eigen::Vector3d& r, const Eigen::Vector3d& v) {
  return 1.0 / (2.0 / r.norm() - v.squaredNorm() / kMu);
}

// SGP4's osculating semi-major axis averaged over one revolution from t_min [m].
double sgp4_revolution_mean_a(const Sgp4Record& rec, double t_min) {
  const double period_min = 2.0 * M_PI / rec.no_unkozai;
  double sum = 0.0;
  constexpr int kSamples = 360;
  for (int k = 0; k < kSamples; ++k) {
    const Sgp4State s = sgp4_propagate(rec, t_min + period_min * k / kSamples);
    const Eigen::Vector3d r(s.position_km[0], s.position_km[1], s.position_km[2]);
    const Eigen::Vector3d v(s.velocity_km_s[0], s.velocity_km_s[1], s.velocity_km_s[2]);
    sum += osculating_a(r * 1e3, v * 1e3);
  }
  return sum / kSamples;
}

TEST(ObservedDecay, BstarRateIsSgp4sOwnDecay) {
  const MeanElements el = elements_of(kIss);
  const Sgp4Record rec = sgp4_initialise(el);
  const double rate = *observed_decay_rate_m_s(el, rec, DecaySignal::kSgp4Bstar);
  // SGP4 itself over two days: the mean over a revolution removes the short-period terms.
  const double a0 = sgp4_revolution_mean_a(rec, 0.0), a2 = sgp4_revolution_mean_a(rec, 2880.0);
  const double sgp4_rate = (a2 - a0) / (2.0 * 86400.0);
  std::printf("ISS: da/dt from C1 %.2f m/day, from SGP4's propagation %.2f m/day\n", rate * 86400.0,
              sgp4_rate * 86400.0);
  EXPECT_LT(rate, 0.0);
  EXPECT_NEAR(rate / sgp4_rate, 1.0, 0.03);
}

TEST(ObservedDecay, MeanMotionDerivativeByKeplersThirdLaw) {
  const MeanElements el = elements_of(kIss);
  const Sgp4Record rec = sgp4_initialise(el);
  const double rate = *observed_decay_rate_m_s(el, rec, DecaySignal::kMeanMotionDerivative);
  // By hand from the published numbers: n = 15.49594026 rev/day, n-dot = 2 x 0.00005958 rev/day^2,
  // a = (mu / n^2)^(1/3) (WGS-72 mu), da/dt = -(2/3) a n-dot / n.
  const double n = 15.49594026 * 2.0 * M_PI / 86400.0;
  const double n_dot = 2.0 * 0.00005958 * 2.0 * M_PI / (86400.0 * 86400.0);
  const double a = std::cbrt(398600.8e9 / (n * n));
  const double expected = -(2.0 / 3.0) * a * n_dot / n;
  EXPECT_NEAR(rate / expected, 1.0, 2e-3);  // SGP4's un-Kozai'd mean motion differs by ~1e-3
}

TEST(ObservedDecay, NoSignalWhenTheOrbitIsNotDecaying) {
  MeanElements el = elements_of(kIss);
  el.mean_motion_dot_rad_min2 = -1e-12;
  el.bstar_per_earth_radius = -1e-4;
  const Sgp4Record rec = sgp4_initialise(el);
  EXPECT_FALSE(observed_decay_rate_m_s(el, rec, DecaySignal::kMeanMotionDerivative));
  EXPECT_FALSE(observed_decay_rate_m_s(el, rec, DecaySignal::kSgp4Bstar));
}

// King-Hele: on a circular orbit in an atmosphere of density rho, co-rotating, da/dt = -(Cd A/m) rho
// sqrt(mu a) F with F = (1 - r omega_E cos i / v)^2 to first order.
TEST(OrbitAveragedDrag, MatchesKingHeleOnACircularOrbit) {
  MeanElements el = elements_of(kIss);
  el.eccentricity = 1e-4;
  const Sgp4Record rec = sgp4_initialise(el);
  ForceModelSettings table;
  const auto per_unit =
      orbit_averaged_decay_per_unit_ballistic(rec, el.epoch, run_atmosphere_density(table, el.epoch));
  ASSERT_TRUE(per_unit);
  const double a = sgp4_mean_semi_major_axis_m(rec);
  const double v = std::sqrt(kMu / a);
  const double f =
      std::pow(1.0 - a * constants::kEarthRotationRate_rad_s * std::cos(el.inclination_rad) / v, 2.0);
  // Density at the mean radius over the equatorial radius, as the force model takes altitude.
  const double king_hele = -DensityTable::standard().density_kg_m3(a - kRe) * std::sqrt(kMu * a) * f;
  std::printf("circular %.0f km: orbit average %.4e, King-Hele %.4e m/s per m^2/kg\n", (a - kRe) * 1e-3,
              *per_unit, king_hele);
  EXPECT_NEAR(*per_unit / king_hele, 1.0, 0.06);
}

// The propagator's decay with a known Cd A/m, reported as an element set's n-dot, is fitted back.
TEST(BallisticFit, RecoversTheCoefficientThePropagatorDecaysWith) {
  MeanElements el = elements_of(kIss);
  const Sgp4Record rec = sgp4_initialise(el);
  constexpr double kTrue = 0.015;
  Population p;
  ObjectRecord o;
  o.id = 1;
  const Sgp4State s = sgp4_propagate(rec, 0.0);
  for (int i = 0; i < 3; ++i) {
    o.position_m[i] = s.position_km[i] * 1e3;
    o.velocity_m_s[i] = s.velocity_km_s[i] * 1e3;
  }
  o.radius_m = 1.0;
  o.mass_kg = 1000.0;
  o.drag_area_to_mass_m2_kg = kTrue;
  p.add(o);
  ForceModelSettings forces;  // density table, J2, C22/S22, drag, SRP
  forces.srp = false;
  SymplecticPropagator propagator(forces, el.epoch);
  // Mean osculating a over the first and the last revolution of two days.
  const double period_s = 2.0 * M_PI / rec.no_unkozai * 60.0;
  constexpr double kDt = 10.0;
  const int per_rev = static_cast<int>(period_s / kDt);
  const int steps = static_cast<int>(2.0 * 86400.0 / kDt);
  double first = 0.0, last = 0.0;
  for (int k = 0; k < steps; ++k) {
    const double a = osculating_a(p.state.position(0), p.state.velocity(0));
    if (k < per_rev) first += a / per_rev;
    if (k >= steps - per_rev) last += a / per_rev;
    propagator.step(p, k * kDt, kDt);
  }
  const double rate = (last - first) / ((steps - per_rev) * kDt);
  // The element set that observed this decay: n-dot from da/dt by Kepler's third law.
  const double n = rec.no_unkozai / 60.0;
  el.mean_motion_dot_rad_min2 = -1.5 * rate * n / sgp4_mean_semi_major_axis_m(rec) * 3600.0 / 2.0;
  Population fitted = p;
  fitted.drag_area_to_mass_m2_kg[0] = 0.0;
  const BallisticFitCounts counts =
      fit_ballistic_coefficients(fitted, {el}, el.epoch, run_atmosphere_density(forces, el.epoch));
  std::printf("propagated with Cd A/m %.4f: %.2f m/day; fitted %.4f m^2/kg\n", kTrue, rate * 86400.0,
              fitted.drag_area_to_mass_m2_kg[0]);
  EXPECT_EQ(counts.from_mean_motion_derivative, 1u);
  EXPECT_NEAR(fitted.drag_area_to_mass_m2_kg[0] / kTrue, 1.0, 0.05);
}

// The reason for the fit: BSTAR is fitted against SGP4's power-law atmosphere, far denser than the
// thermosphere at 760 km at solar minimum, so 2 B* / rho0 is several times too small there.
TEST(BallisticFit, HighDebrisAtSolarMinimumNeedsMoreThanTheBstarRule) {
  const MeanElements el = elements_of(kThoradDebris);
  Population p;
  ObjectRecord o;
  o.id = el.catalog_number;
  o.position_m = Eigen::Vector3d(kRe + 760e3, 0, 0);
  o.velocity_m_s = Eigen::Vector3d(0, 7470, 0);
  o.radius_m = 0.1;
  o.mass_kg = 1.0;
  p.add(o);
  ForceModelSettings msis;
  msis.atmosphere = AtmosphereModel::kNrlmsise00;
  for (DecaySignal signal : {DecaySignal::kMeanMotionDerivative, DecaySignal::kSgp4Bstar}) {
    BallisticFitSettings settings;
    settings.first_signal = signal;
    const BallisticFitCounts c =
        fit_ballistic_coefficients(p, {el}, el.epoch, run_atmosphere_density(msis, el.epoch), settings);
    const double rule = 2.0 * el.bstar_per_earth_radius / constants::kBstarRho0_kg_m2_per_er;
    std::printf("760 km, 2019-03: fitted %.4f m^2/kg (%s), BSTAR rule %.4f (x%.1f)\n",
                p.drag_area_to_mass_m2_kg[0], signal == DecaySignal::kSgp4Bstar ? "BSTAR" : "n-dot", rule,
                c.median_ratio_to_bstar_mapping);
    EXPECT_GT(c.median_ratio_to_bstar_mapping, 3.0);
  }
}

TEST(BallisticFit, ObjectsWithoutSignalKeepTheirCoefficientAndAreCounted) {
  MeanElements decaying = elements_of(kIss), raising = elements_of(kIss);
  raising.mean_motion_dot_rad_min2 = -1e-12;
  raising.bstar_per_earth_radius = -1e-5;
  MeanElements bstar_only = elements_of(kIss);
  bstar_only.mean_motion_dot_rad_min2 = 0.0;
  Population p;
  for (ObjectId id : {1, 2, 3}) {
    ObjectRecord o;
    o.id = id;
    o.position_m = Eigen::Vector3d(kRe + 420e3, 0, 0);
    o.velocity_m_s = Eigen::Vector3d(0, 7660, 0);
    o.radius_m = 1.0;
    o.mass_kg = 100.0;
    o.drag_area_to_mass_m2_kg = 0.5;
    p.add(o);
  }
  ForceModelSettings table;
  const BallisticFitCounts c = fit_ballistic_coefficients(p, {decaying, raising, bstar_only}, decaying.epoch,
                                                          run_atmosphere_density(table, decaying.epoch));
  EXPECT_EQ(c.from_mean_motion_derivative, 1u);
  EXPECT_EQ(c.from_sgp4_bstar, 1u);
  EXPECT_EQ(c.no_signal, 1u);
  EXPECT_NE(p.drag_area_to_mass_m2_kg[0], 0.5);
  EXPECT_EQ(p.drag_area_to_mass_m2_kg[1], 0.5);
  EXPECT_NE(p.drag_area_to_mass_m2_kg[2], 0.5);
  EXPECT_THROW(fit_ballistic_coefficients(p, {decaying}, decaying.epoch,
                                          run_atmosphere_density(table, decaying.epoch)),
               std::invalid_argument);
}

}  // namespace
}  // namespace kessler
