// The step loop may evaluate both sides of a select (if-conversion) only if floating-point operations
// are assumed not to trap; without that, GCC vectorises it only where AVX-512 masks exist. This changes
// no value (IEEE results are the same; only exception flags could differ, and the core reads none), so
// SIMD and scalar paths still give identical bits (tested).
#pragma GCC optimize("no-trapping-math")

#include "core/integration/symplectic_propagator.hpp"

#include "core/integration/burn_up.hpp"
#include "core/parallel/team_timeline.hpp"
#include "core/parallel/thread_chunks.hpp"
#include "core/physics/constants.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

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

// One composed step's coefficients at one time: the force instants of the kicks and the drift and
// kick lengths (the composition's weights times the step).
struct StepPlan {  // NOLINT(bugprone-reserved-identifier): clang-tidy 14 flags the implicit copy's array loop
  ForceInstant f[Composition::kMaxKicks];
  double drift[Composition::kMaxKicks + 1];
  double kick_length[Composition::kMaxKicks];
  int kicks = 0;
  AtmosphereModel atmosphere = AtmosphereModel::kExponentialFit;
  // DragCoupling::kStepEnds: drag's flows over half the step at its start and at its end, and their
  // instants; the kicks are then conservative.
  bool drag_at_step_ends = false;
  double drag_half_s = 0.0;
  ForceInstant drag_start, drag_end;
};

StepPlan plan_step(const ForceModel& model, const Composition& c, double t_start_s, double dt_s) {
  StepPlan plan;
  plan.kicks = c.kicks;
  plan.atmosphere = model.settings().atmosphere;
  plan.drag_at_step_ends = model.settings().drag_coupling == DragCoupling::kStepEnds;
  // Drag rate k |v_rel| times the longest kick (or the step, with drag at its ends) at most 1/4, i.e. at
  // most 1/8 per half-flow, so a kick's drag changes v_rel by a factor in [1/1.125^2, 1/0.875^2]
  // (drag.hpp): inactive above ~100 km.
  const double drag_span = plan.drag_at_step_ends ? 1.0 : c.largest_kick();
  const double drag_limit = SymplecticPropagator::kDragRateLimitPerKick / (drag_span * dt_s);
  if (plan.drag_at_step_ends) {
    plan.drag_half_s = 0.5 * dt_s;
    plan.drag_start = model.instant(t_start_s);
    plan.drag_end = model.instant(t_start_s + dt_s);
    plan.drag_start.drag_rate_limit_per_s = drag_limit;
    plan.drag_end.drag_rate_limit_per_s = drag_limit;
  }
  for (int k = 0; k < c.kicks; ++k) {
    const auto u = static_cast<std::size_t>(k);
    plan.f[k] = model.instant(t_start_s + c.kick_time[u] * dt_s, !plan.drag_at_step_ends);
    plan.f[k].drag_rate_limit_per_s = drag_limit;
    plan.kick_length[k] = c.kick[u] * dt_s;
  }
  for (int k = 0; k <= c.kicks; ++k) plan.drift[k] = c.drift[static_cast<std::size_t>(k)] * dt_s;
  return plan;
}

// Low objects sub-stepped at once, by the thread that stepped their blocks, as soon as its blocks have
// given this many (and the rest after its last block): enough to fill the vector lanes, while the
// claiming of blocks still shares the work out (low objects cluster in the catalog: decaying debris of one
// launch or breakup sits together). Sharing them out evenly after a barrier cost as much, in lines
// written back to other cores.
constexpr std::size_t kLowBatch = 16;

// Objects per tile of the step kernel below: their states (6 x 8 bytes each) stay in L1 from one kick
// to the next.
constexpr long kTileObjects = 256;

// How one drift-kick pass of the step kernel treats drag: inside each kick (DragCoupling::kEveryKick),
// not at all (a conservative kick between the step's ends), or as the flow over half the step at the start
// position before the first drift (DragCoupling::kStepEnds, first pass).
enum class KickPass { kWithDrag, kConservative, kStartDragThenConservative };

// One drift and kick of every object of the tile [tile, tile_end): a vector loop whose states go back to
// their arrays (in L1) for the next pass.
template <AtmosphereModel kAtmosphere, KickPass kPass>
void drift_kick_pass(const StepArrays& s, long tile, long tile_end, const StepPlan& plan, int k) {
  double* __restrict px = s.x;
  double* __restrict py = s.y;
  double* __restrict pz = s.z;
  double* __restrict pvx = s.vx;
  double* __restrict pvy = s.vy;
  double* __restrict pvz = s.vz;
  const double* __restrict pcda = s.drag_area_to_mass;
  const double* __restrict pam = s.srp_area_to_mass;
  // Copies on the stack: the vectoriser then knows no store in the loop changes them (it would not hoist
  // the NRLMSISE-00 grid's pointer out of the plan, and left that loop scalar).
  const ForceInstant instant = plan.f[k];
  const ForceInstant drag_start = plan.drag_start;
  const double drag_half_s = plan.drag_half_s;
  const double drift = plan.drift[k], kick_length = plan.kick_length[k];
#pragma omp simd
  for (long i = tile; i < tile_end; ++i) {
    double x = px[i], y = py[i], z = pz[i];
    double vx = pvx[i], vy = pvy[i], vz = pvz[i];
    if constexpr (kPass == KickPass::kStartDragThenConservative)
      drag_flow_at<kAtmosphere>(drag_start, drag_half_s, x, y, z, vx, vy, vz, pcda[i]);
    x += drift * vx;
    y += drift * vy;
    z += drift * vz;
    if constexpr (kPass == KickPass::kWithDrag)
      kick<kAtmosphere>(instant, kick_length, x, y, z, vx, vy, vz, pcda[i], pam[i]);
    else
      conservative_kick(instant, kick_length, x, y, z, vx, vy, vz, pam[i]);
    px[i] = x, py[i] = y, pz[i] = z;
    pvx[i] = vx, pvy[i] = vy, pvz[i] = vz;
  }
}

// The step's last drift of the tile [tile, tile_end), then (kDragAtEnd) drag's flow over half the step at
// the end position, and the burn-up test on the end position while it is in registers (when flags is not
// null).
template <AtmosphereModel kAtmosphere, bool kDragAtEnd>
[[gnu::always_inline]] inline void last_drift_pass(const StepArrays& s, long tile, long tile_end,
                                                   const StepPlan& plan, char* __restrict burn_up_flags,
                                                   double burn_up_radius2) {
  double* __restrict px = s.x;
  double* __restrict py = s.y;
  double* __restrict pz = s.z;
  double* __restrict pvx = s.vx;
  double* __restrict pvy = s.vy;
  double* __restrict pvz = s.vz;
  const double* __restrict pcda = s.drag_area_to_mass;
  const double last_drift = plan.drift[plan.kicks];
  const ForceInstant drag_end = plan.drag_end;  // a copy, as in drift_kick_pass
  const double drag_half_s = plan.drag_half_s;
  if (burn_up_flags == nullptr) {
#pragma omp simd
    for (long i = tile; i < tile_end; ++i) {
      const double x = px[i] + last_drift * pvx[i], y = py[i] + last_drift * pvy[i],
                   z = pz[i] + last_drift * pvz[i];
      px[i] = x, py[i] = y, pz[i] = z;
      if constexpr (kDragAtEnd)
        drag_flow_at<kAtmosphere>(drag_end, drag_half_s, x, y, z, pvx[i], pvy[i], pvz[i], pcda[i]);
    }
  } else {
#pragma omp simd
    for (long i = tile; i < tile_end; ++i) {
      const double x = px[i] + last_drift * pvx[i], y = py[i] + last_drift * pvy[i],
                   z = pz[i] + last_drift * pvz[i];
      px[i] = x, py[i] = y, pz[i] = z;
      if constexpr (kDragAtEnd)
        drag_flow_at<kAtmosphere>(drag_end, drag_half_s, x, y, z, pvx[i], pvy[i], pvz[i], pcda[i]);
      burn_up_flags[i] = burns_up(x, y, z, burn_up_radius2);
    }
  }
}

// Objects [begin, end) of `s`, one step. The start states are written to `start` and the burn-up flags
// set (when not null) in the same pass. No OpenMP region of its own: callers split the objects between their
// threads. Tile by tile, each drift-kick of the composition is one vector loop over the tile's objects, whose
// states go back to their arrays (in L1) between kicks. (One loop over the objects with all kicks unrolled
// inside kept the states in registers, but its ~50 KB of code ran from L2, and its speed changed by 25 % with
// where the binary's pages fell: leo-19647 took 87 ns per object-step in the propagator, 60 tiled. Every
// object sees the same operations in the same order: the same bits.)
template <AtmosphereModel kAtmosphere, bool kKeepStart, int kKicks, bool kDragAtStepEnds>
void composed_range(const StepArrays& s, long begin, long end, const StepPlan& plan, StateArrays* start,
                    char* __restrict burn_up_flags, double burn_up_radius2) {
  for (long tile = begin; tile < end; tile += kTileObjects) {
    const long tile_end = std::min(end, tile + kTileObjects);
    if constexpr (kKeepStart) {
      double* __restrict sx = start->x.data();
      double* __restrict sy = start->y.data();
      double* __restrict sz = start->z.data();
      double* __restrict svx = start->vx.data();
      double* __restrict svy = start->vy.data();
      double* __restrict svz = start->vz.data();
#pragma omp simd
      for (long i = tile; i < tile_end; ++i) {
        sx[i] = s.x[i], sy[i] = s.y[i], sz[i] = s.z[i];
        svx[i] = s.vx[i], svy[i] = s.vy[i], svz[i] = s.vz[i];
      }
    }
    if constexpr (kDragAtStepEnds) {
      drift_kick_pass<kAtmosphere, KickPass::kStartDragThenConservative>(s, tile, tile_end, plan, 0);
#pragma GCC unroll 1
      for (int k = 1; k < kKicks; ++k)
        drift_kick_pass<kAtmosphere, KickPass::kConservative>(s, tile, tile_end, plan, k);
    } else {
#pragma GCC unroll 1
      for (int k = 0; k < kKicks; ++k)
        drift_kick_pass<kAtmosphere, KickPass::kWithDrag>(s, tile, tile_end, plan, k);
    }
    last_drift_pass<kAtmosphere, kDragAtStepEnds>(s, tile, tile_end, plan, burn_up_flags, burn_up_radius2);
  }
}

template <int kKicks>
void range_with(const StepArrays& s, long begin, long end, const StepPlan& plan, StateArrays* start,
                char* burn_up_flags, double burn_up_radius2) {
  constexpr auto kTable = AtmosphereModel::kDensityTable, kFit = AtmosphereModel::kExponentialFit,
                 kMsis = AtmosphereModel::kNrlmsise00;
  auto with_coupling = [&]<AtmosphereModel kAtmosphere, bool kDragAtStepEnds>() {
    if (start != nullptr)
      composed_range<kAtmosphere, true, kKicks, kDragAtStepEnds>(s, begin, end, plan, start, burn_up_flags,
                                                                 burn_up_radius2);
    else
      composed_range<kAtmosphere, false, kKicks, kDragAtStepEnds>(s, begin, end, plan, nullptr, burn_up_flags,
                                                                  burn_up_radius2);
  };
  auto run = [&]<AtmosphereModel kAtmosphere>() {
    if (plan.drag_at_step_ends)
      with_coupling.template operator()<kAtmosphere, true>();
    else
      with_coupling.template operator()<kAtmosphere, false>();
  };
  switch (plan.atmosphere) {
    case AtmosphereModel::kDensityTable:
      run.template operator()<kTable>();
      break;
    case AtmosphereModel::kNrlmsise00:
      run.template operator()<kMsis>();
      break;
    default:
      run.template operator()<kFit>();
      break;
  }
}

// Objects [begin, end) of `s`, one step; their start states copied to `start` and their burn-up flags
// set (burns_up with burn_up_radius2) where those are not null.
void step_range(const StepArrays& s, long begin, long end, const StepPlan& plan, StateArrays* start,
                char* burn_up_flags = nullptr, double burn_up_radius2 = 0.0) {
  if (plan.kicks == 3)
    range_with<3>(s, begin, end, plan, start, burn_up_flags, burn_up_radius2);
  else if (plan.kicks == 7)
    range_with<7>(s, begin, end, plan, start, burn_up_flags, burn_up_radius2);
  else
    throw std::logic_error("SymplecticPropagator: no kernel for this composition");
}

// States [begin, end) of `from` copied to `to` (sized already).
void copy_states(const StateArrays& from, std::size_t begin, std::size_t end, StateArrays& to) {
  for (auto [src, dst] :
       {std::pair{&from.x, &to.x}, std::pair{&from.y, &to.y}, std::pair{&from.z, &to.z},
        std::pair{&from.vx, &to.vx}, std::pair{&from.vy, &to.vy}, std::pair{&from.vz, &to.vz}})
    std::copy(src->begin() + static_cast<std::ptrdiff_t>(begin),
              src->begin() + static_cast<std::ptrdiff_t>(end),
              dst->begin() + static_cast<std::ptrdiff_t>(begin));
}

}  // namespace

SymplecticPropagator::SymplecticPropagator(const ForceModelSettings& forces, const UtcEpoch& epoch,
                                           Integrator integrator, TeamTimeline* timeline)
    : model_(forces, epoch),
      integrator_(integrator),
      composition_(composition_of(integrator)),
      timeline_(timeline) {}

void SymplecticPropagator::step(Population& population, double t_start_s, double dt_s) {
  step_with(population, t_start_s, dt_s, StepRequest{});
}

void SymplecticPropagator::step_with(Population& population, double t_start_s, double dt_s,
                                     const StepRequest& request) {
  StateArrays* const start_out = request.start_out;
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
  StateArrays* const end_out = request.end_out;
  if (end_out != nullptr) end_out->resize(n);
  // The burn-up flags in the same pass: each block's, and each low object's again after its sub-steps.
  char* burn_up_flags = nullptr;
  if (request.burn_up_flags != nullptr) {
    request.burn_up_flags->resize(n);
    burn_up_flags = request.burn_up_flags->data();
  }
  const double burn_up_radius2 = request.burn_up_radius2;
  if (n == 0) return;
  StepArrays arrays{st.x.data(),
                    st.y.data(),
                    st.z.data(),
                    st.vx.data(),
                    st.vy.data(),
                    st.vz.data(),
                    population.drag_area_to_mass_m2_kg.data(),
                    population.srp_area_to_mass_m2_kg.data()};
  const int threads =
      n >= kPropagationParallelMinimum ? (threads_ > 0 ? threads_ : omp_get_max_threads()) : 1;

  // Objects that start the step low in the atmosphere take kLowAltitudeSubsteps steps of dt / k instead
  // (on copies of their states, written back after the main pass). The choice depends on the object's
  // own state alone, so it is the same for any thread count and after a restart.
  const double low_radius_m = constants::kEarthEquatorialRadius_m + kLowAltitude_m;
  const double low_radius2 = low_radius_m * low_radius_m;
  const bool substep_low = model_.settings().drag;
  const StepPlan plan = plan_step(model_, composition_, t_start_s, dt_s);
  StepPlan sub_plans[kLowAltitudeSubsteps];
  if (substep_low) {
    const double h = dt_s / kLowAltitudeSubsteps;
    for (int sub = 0; sub < kLowAltitudeSubsteps; ++sub)
      sub_plans[sub] = plan_step(model_, composition_, t_start_s + sub * h, h);
    low_flag_.resize(n);
  }
  low_by_thread_.resize(static_cast<std::size_t>(threads));
  for (ThreadLow& low : low_by_thread_) low.clear();  // OpenMP may give fewer threads
  // Blocks of a sixteenth of a chunk, at least 64 objects (~0.6% of a block's work goes to claiming it).
  const std::size_t chunk = n / static_cast<std::size_t>(threads);
  // Chunks of equal cost, from the last step's low objects: they stay low for many steps. (Burn-ups
  // may have shifted some indices since; a chunk a few objects off only costs a little balance.)
  chunks_.weighted(n, static_cast<std::size_t>(threads), low_, kLowObjectExtraCost);
  blocks_.reset(chunks_, std::max<std::size_t>(chunk / 16, 64));
  TeamTimeline* const timeline = timeline_;
  if (timeline) timeline->region_start(static_cast<std::size_t>(threads));
#pragma omp parallel num_threads(threads)
  {
    // One region, no barrier: blocks of each thread's own chunk first (thread_chunks.hpp), so most
    // objects are propagated on the core that reads them next, then blocks left in other chunks; before
    // a block is stepped, its low objects are copied aside, and sub-stepped in batches (kLowBatch).
    const std::size_t t = static_cast<std::size_t>(omp_get_thread_num());
    if (timeline) timeline->enter(t);
    ThreadLow& mine = low_by_thread_[t];
    ChunkBlocks::Claimer claimer = blocks_.claimer(t);
    // The low objects' sub-steps, on their copies, and the copies written back: objects [lo, hi) of
    // this thread's list.
    auto substep = [&](std::size_t lo, std::size_t hi) {
      const StepArrays low = mine.arrays();
      for (int sub = 0; sub < kLowAltitudeSubsteps; ++sub)
        step_range(low, static_cast<long>(lo), static_cast<long>(hi), sub_plans[sub], nullptr);
      for (std::size_t k = lo; k < hi; ++k) {
        const std::size_t i = mine.index[k];
        st.x[i] = low.x[k], st.y[i] = low.y[k], st.z[i] = low.z[k];
        st.vx[i] = low.vx[k], st.vy[i] = low.vy[k], st.vz[i] = low.vz[k];
        if (burn_up_flags != nullptr)
          burn_up_flags[i] = burns_up(low.x[k], low.y[k], low.z[k], burn_up_radius2);
        if (end_out != nullptr) {
          StateArrays& e = *end_out;
          e.x[i] = low.x[k], e.y[i] = low.y[k], e.z[i] = low.z[k];
          e.vx[i] = low.vx[k], e.vy[i] = low.vy[k], e.vz[i] = low.vz[k];
        }
      }
    };
    std::size_t substepped = 0;  // of this thread's list
    for (std::size_t begin = 0, end = 0; claimer.next(begin, end);) {
      if (substep_low) mine.copy_low(population, low_flag_.data(), begin, end, low_radius2);
      step_range(arrays, static_cast<long>(begin), static_cast<long>(end), plan, start_out, burn_up_flags,
                 burn_up_radius2);
      // The end states while the block is in this core's cache (a low object's again after its sub-steps).
      if (end_out != nullptr) copy_states(st, begin, end, *end_out);
      if (mine.index.size() - substepped >= kLowBatch) {
        substep(substepped, mine.index.size());
        substepped = mine.index.size();
      }
    }
    if (mine.index.size() > substepped) substep(substepped, mine.index.size());
    if (timeline) timeline->mark(t, kPropBlocks);
  }
  if (timeline) timeline->region_end();
  low_.clear();
  for (const ThreadLow& low : low_by_thread_) low_.insert(low_.end(), low.index.begin(), low.index.end());
  std::sort(low_.begin(), low_.end());  // population order, whoever took which block
}

void SymplecticPropagator::ThreadLow::clear() {
  index.clear();
  for (std::vector<double>& column : state) column.clear();
}

void SymplecticPropagator::ThreadLow::copy_low(const Population& population, char* flag, std::size_t begin,
                                               std::size_t end, double low_radius2) {
  const StateArrays& st = population.state;
  const double* __restrict x = st.x.data();
  const double* __restrict y = st.y.data();
  const double* __restrict z = st.z.data();
#pragma omp simd
  for (std::size_t i = begin; i < end; ++i) flag[i] = x[i] * x[i] + y[i] * y[i] + z[i] * z[i] < low_radius2;
  for_each_flagged(flag, begin, end, [&](std::size_t i) {
    index.push_back(static_cast<std::uint32_t>(i));
    const double values[8] = {st.x[i],
                              st.y[i],
                              st.z[i],
                              st.vx[i],
                              st.vy[i],
                              st.vz[i],
                              population.drag_area_to_mass_m2_kg[i],
                              population.srp_area_to_mass_m2_kg[i]};
    for (int c = 0; c < 8; ++c) state[static_cast<std::size_t>(c)].push_back(values[c]);
  });
}

SymplecticPropagator::StepArrays SymplecticPropagator::ThreadLow::arrays() {
  return StepArrays{state[0].data(), state[1].data(), state[2].data(), state[3].data(),
                    state[4].data(), state[5].data(), state[6].data(), state[7].data()};
}

void validate_for_propagation(const Population& population) {
  if (auto problem = population.validate()) throw std::invalid_argument(*problem);
}

}  // namespace kessler
