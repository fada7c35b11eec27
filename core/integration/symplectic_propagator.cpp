// The step loop may evaluate both sides of a select (if-conversion) only if floating-point operations
// are assumed not to trap; without that, GCC vectorises it only where AVX-512 masks exist. This changes
// no value (IEEE results are the same; only exception flags could differ, and the core reads none), so
// SIMD and scalar paths still give identical bits (tested).
#pragma GCC optimize("no-trapping-math")

#include "core/integration/symplectic_propagator.hpp"

#include "core/physics/constants.hpp"

#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include <omp.h>

namespace kessler {

struct SymplecticPropagator::StepArrays {
  double* x;
  double* y;
  double* z;
  double* vx;
  double* vy;
  double* vz;
  const double* drag_area_to_mass;
  const double* srp_area_to_mass;
};

namespace {

using StepArrays = SymplecticPropagator::StepArrays;

// The start states are written to `start` (when not null) in the same pass. drift and kick hold the
// composition's weights times dt; f the force instants of the kicks.
template <AtmosphereModel kAtmosphere, bool kKeepStart, int kKicks>
void composed_step(const StepArrays& s, std::size_t n, const ForceInstant* f, const double* drift,
                   const double* kick_length, int threads, StateArrays* start) {
  double a[kKicks + 1], b[kKicks];
  for (int k = 0; k <= kKicks; ++k) a[k] = drift[k];
  for (int k = 0; k < kKicks; ++k) b[k] = kick_length[k];
  const long count = static_cast<long>(n);
  // Local pointers: the loop must not re-read them through `s` (a store could alias it in principle).
  double* __restrict px = s.x;
  double* __restrict py = s.y;
  double* __restrict pz = s.z;
  double* __restrict pvx = s.vx;
  double* __restrict pvy = s.vy;
  double* __restrict pvz = s.vz;
  const double* __restrict pcda = s.drag_area_to_mass;
  const double* __restrict pam = s.srp_area_to_mass;
  double* __restrict sx = kKeepStart ? start->x.data() : nullptr;
  double* __restrict sy = kKeepStart ? start->y.data() : nullptr;
  double* __restrict sz = kKeepStart ? start->z.data() : nullptr;
  double* __restrict svx = kKeepStart ? start->vx.data() : nullptr;
  double* __restrict svy = kKeepStart ? start->vy.data() : nullptr;
  double* __restrict svz = kKeepStart ? start->vz.data() : nullptr;
// Tiny populations (tests, tools, the low objects' sub-steps) run on a team of one: more threads cost
// more than they save. (Not an `if` clause: GCC then runs the loop unvectorised, 7x slower per object.)
#pragma omp parallel for simd schedule(static) num_threads(count >= 512 ? threads : 1)
  for (long i = 0; i < count; ++i) {
    double x = px[i], y = py[i], z = pz[i];
    double vx = pvx[i], vy = pvy[i], vz = pvz[i];
    const double cda = pcda[i], am = pam[i];
    if constexpr (kKeepStart) {
      sx[i] = x, sy[i] = y, sz[i] = z;
      svx[i] = vx, svy[i] = vy, svz[i] = vz;
    }
#pragma GCC unroll 8
    for (int k = 0; k < kKicks; ++k) {
      x += a[k] * vx;
      y += a[k] * vy;
      z += a[k] * vz;
      kick<kAtmosphere>(f[k], b[k], x, y, z, vx, vy, vz, cda, am);
    }
    x += a[kKicks] * vx;
    y += a[kKicks] * vy;
    z += a[kKicks] * vz;
    px[i] = x;
    py[i] = y;
    pz[i] = z;
    pvx[i] = vx;
    pvy[i] = vy;
    pvz[i] = vz;
  }
}

template <int kKicks>
void step_with(AtmosphereModel atmosphere, const StepArrays& s, std::size_t n, const ForceInstant* f,
               const double* drift, const double* kick_length, int threads, StateArrays* start) {
  const bool table = atmosphere == AtmosphereModel::kDensityTable;
  if (start != nullptr) {
    if (table)
      composed_step<AtmosphereModel::kDensityTable, true, kKicks>(s, n, f, drift, kick_length, threads,
                                                                  start);
    else
      composed_step<AtmosphereModel::kExponentialFit, true, kKicks>(s, n, f, drift, kick_length, threads,
                                                                    start);
  } else {
    if (table)
      composed_step<AtmosphereModel::kDensityTable, false, kKicks>(s, n, f, drift, kick_length, threads,
                                                                   nullptr);
    else
      composed_step<AtmosphereModel::kExponentialFit, false, kKicks>(s, n, f, drift, kick_length, threads,
                                                                     nullptr);
  }
}

}  // namespace

SymplecticPropagator::SymplecticPropagator(const ForceModelSettings& forces, const UtcEpoch& epoch,
                                           Integrator integrator)
    : model_(forces, epoch), integrator_(integrator), composition_(composition_of(integrator)) {}

void SymplecticPropagator::step(Population& population, double t_start_s, double dt_s) {
  advance(population, t_start_s, dt_s, nullptr);
}

void SymplecticPropagator::step_keeping_start(Population& population, double t_start_s, double dt_s,
                                              StateArrays& start_out) {
  advance(population, t_start_s, dt_s, &start_out);
}

void SymplecticPropagator::advance(Population& population, double t_start_s, double dt_s,
                                   StateArrays* start_out) {
  if (!std::isfinite(dt_s) || dt_s <= 0.0)
    throw std::invalid_argument("SymplecticPropagator: dt_s must be finite and positive, got " +
                                std::to_string(dt_s));
  if (!std::isfinite(t_start_s)) throw std::invalid_argument("SymplecticPropagator: t_start_s is not finite");
  const std::size_t n = population.size();
  StateArrays& st = population.state;
  if (st.x.size() != n || st.y.size() != n || st.z.size() != n || st.vx.size() != n || st.vy.size() != n ||
      st.vz.size() != n || population.drag_area_to_mass_m2_kg.size() != n ||
      population.srp_area_to_mass_m2_kg.size() != n)
    throw std::invalid_argument("SymplecticPropagator: population arrays differ in length");
  if (start_out != nullptr) start_out->resize(n);
  if (n == 0) return;
  StepArrays arrays{st.x.data(),
                    st.y.data(),
                    st.z.data(),
                    st.vx.data(),
                    st.vy.data(),
                    st.vz.data(),
                    population.drag_area_to_mass_m2_kg.data(),
                    population.srp_area_to_mass_m2_kg.data()};
  const int threads = threads_ > 0 ? threads_ : omp_get_max_threads();

  // Objects that start the step low in the atmosphere take kLowAltitudeSubsteps steps of dt / k instead
  // (on copies of their states, merged after the main pass). The choice depends on the object's own
  // state alone, so it is the same for any thread count and after a restart.
  const double low_radius_m = constants::kEarthEquatorialRadius_m + kLowAltitude_m;
  const double low_radius2 = low_radius_m * low_radius_m;
  low_.clear();
  if (model_.settings().drag) {
    // Flagged by the threads that propagate the same chunks (a serial scan would read every other
    // core's freshly written positions, and those cores would then pay to write them again), then
    // listed in population order from one byte per object.
    low_flag_.resize(n);
    const double* __restrict x = st.x.data();
    const double* __restrict y = st.y.data();
    const double* __restrict z = st.z.data();
    char* __restrict flag = low_flag_.data();
    const long count = static_cast<long>(n);
#pragma omp parallel for simd schedule(static) num_threads(count >= 512 ? threads : 1)
    for (long i = 0; i < count; ++i) flag[i] = x[i] * x[i] + y[i] * y[i] + z[i] * z[i] < low_radius2;
    for (const char* p = flag; (p = static_cast<const char*>(std::memchr(p, 1, n - (p - flag)))) != nullptr;
         ++p) {
      low_.push_back(static_cast<std::uint32_t>(p - flag));
      if (p - flag + 1 == count) break;
    }
  }
  if (!low_.empty()) {
    const std::size_t m = low_.size();
    low_state_.resize(8 * m);
    double* c = low_state_.data();
    for (std::size_t k = 0; k < m; ++k) {
      const std::size_t i = low_[k];
      c[k] = st.x[i], c[m + k] = st.y[i], c[2 * m + k] = st.z[i];
      c[3 * m + k] = st.vx[i], c[4 * m + k] = st.vy[i], c[5 * m + k] = st.vz[i];
      c[6 * m + k] = population.drag_area_to_mass_m2_kg[i];
      c[7 * m + k] = population.srp_area_to_mass_m2_kg[i];
    }
    const StepArrays low{c, c + m, c + 2 * m, c + 3 * m, c + 4 * m, c + 5 * m, c + 6 * m, c + 7 * m};
    const double h = dt_s / kLowAltitudeSubsteps;
    for (int sub = 0; sub < kLowAltitudeSubsteps; ++sub) step_arrays(low, m, t_start_s + sub * h, h, 1);
  }
  step_arrays(arrays, n, t_start_s, dt_s, threads, start_out);
  if (!low_.empty()) {
    const std::size_t m = low_.size();
    const double* c = low_state_.data();
    for (std::size_t k = 0; k < m; ++k) {
      const std::size_t i = low_[k];
      st.x[i] = c[k], st.y[i] = c[m + k], st.z[i] = c[2 * m + k];
      st.vx[i] = c[3 * m + k], st.vy[i] = c[4 * m + k], st.vz[i] = c[5 * m + k];
    }
  }
}

void SymplecticPropagator::step_arrays(const StepArrays& arrays, std::size_t n, double t_start_s, double dt_s,
                                       int threads, StateArrays* start_out) const {
  const Composition& c = composition_;
  ForceInstant f[Composition::kMaxKicks];
  double drift[Composition::kMaxKicks + 1], kick_length[Composition::kMaxKicks];
  // Drag rate k |v_rel| times the longest kick at most 1/4, i.e. at most 1/8 per half-flow, so a kick's
  // drag changes v_rel by a factor in [1/1.125^2, 1/0.875^2] (drag.hpp): inactive above ~100 km.
  const double drag_limit = kDragRateLimitPerKick / (c.largest_kick() * dt_s);
  for (int k = 0; k < c.kicks; ++k) {
    const auto u = static_cast<std::size_t>(k);
    f[k] = model_.instant(t_start_s + c.kick_time[u] * dt_s);
    f[k].drag_rate_limit_per_s = drag_limit;
    kick_length[k] = c.kick[u] * dt_s;
  }
  for (int k = 0; k <= c.kicks; ++k) drift[k] = c.drift[static_cast<std::size_t>(k)] * dt_s;
  const AtmosphereModel atmosphere = model_.settings().atmosphere;
  if (c.kicks == 3)
    step_with<3>(atmosphere, arrays, n, f, drift, kick_length, threads, start_out);
  else if (c.kicks == 7)
    step_with<7>(atmosphere, arrays, n, f, drift, kick_length, threads, start_out);
  else
    throw std::logic_error("SymplecticPropagator: no kernel for this composition");
}

void validate_for_propagation(const Population& population) {
  if (auto problem = population.validate()) throw std::invalid_argument(*problem);
}

}  // namespace kessler
