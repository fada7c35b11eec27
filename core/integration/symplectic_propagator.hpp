// The numerical propagator: a symmetric composition of drift and kick steps (composition.hpp) under the
// full force model (force_model.hpp), each kick's force at its true sub-step time. Two compositions, both
// 4th order: the paper's Yoshida (1990) with 3 force evaluations per step, and Blanes & Moan's (2002)
// SRKN_6^b with 7, whose error constant is about 10^4 times smaller (so it takes a 3x longer step with
// an error two orders of magnitude smaller; composition.hpp).
//
// One pass over the population per step: each object runs the whole step in registers (structure of
// arrays in, same arrays out), the per-instant scalars (Earth angle, Sun position) computed once per
// sub-step. The loop is OpenMP-parallel and SIMD-vectorised over objects; each object's arithmetic
// depends on that object alone and uses only IEEE-exact operations (no FMA contraction, no libm), so
// the result is bitwise identical for any thread count and any vector/scalar split. Objects that start a
// step below 300 km take four sub-steps instead (kLowAltitude_m below), on copies, in batches.
//
// Drag depends on velocity. Each kick of length h (= d_i dt) is therefore itself a symmetric splitting
// at its fixed position (force_model.hpp, kick): drag's exact flow over h/2, the velocity-independent
// kick, drag's exact flow over h/2 again. The kick is then time-symmetric, so every composition stays
// symmetric and 4th order with drag (measured: tests/physics,
// Yoshida.LowPerigeeDragKeepsFourthOrder); with drag the scheme is symplectic only in its conservative
// part. With ForceModelSettings::drag_coupling = kStepEnds, drag's flow over dt/2 is applied at the step's
// start and end positions instead, around conservative kicks: 2nd order in drag, two density reads per
// step instead of one per kick (force_model_settings.hpp). Deep in the atmosphere (below about 100 km)
// the drag rate is capped so that rate x |h| <= kDragRateLimitPerKick over the longest kick (the step,
// with drag at its ends), which keeps the exact drag flow finite in Yoshida's negative middle kick (never
// active above the 150 km burn-up altitude).
//
// Input checks: step() refuses inconsistent arrays and a non-finite or non-positive dt
// (std::invalid_argument). Physical soundness of each object (finite states above the surface, positive
// radius and mass, non-negative areas) is the caller's job when objects enter the population:
// validate_for_propagation() does it and throws naming the object and the field.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/integration/composition.hpp"
#include "core/integration/propagator.hpp"
#include "core/parallel/thread_chunks.hpp"
#include "core/physics/force_model.hpp"

namespace kessler {

class SymplecticPropagator final : public Propagator {
 public:
  // timeline: where each step's threads are timed (team_timeline.hpp, PropagatorSegment); null: untimed.
  SymplecticPropagator(const ForceModelSettings& forces, const UtcEpoch& epoch,
                       Integrator integrator = Integrator::kBlanesMoan4, TeamTimeline* timeline = nullptr);

  void step(Population& population, double t_start_s, double dt_s) override;
  // The start states and the burn-up flags in the step's own parallel pass.
  void step_with(Population& population, double t_start_s, double dt_s, const StepRequest& request) override;

  // OpenMP threads for step(); 0 (default) uses OpenMP's default.
  void set_threads(int threads) { threads_ = threads; }
  int threads() const { return threads_; }

  const ForceModel& force_model() const { return model_; }

  Integrator integrator() const { return integrator_; }

  // Yoshida's coefficients: drifts c1..c4, kicks d1..d3 (composition.hpp).
  static constexpr double kW1 = composition::kYoshidaW1;  // 1 / (2 - 2^(1/3))
  static constexpr double kW0 = composition::kYoshidaW0;  // -2^(1/3) / (2 - 2^(1/3))
  static constexpr double kC1 = kW1 / 2.0, kC2 = (kW0 + kW1) / 2.0;
  static constexpr double kD1 = kW1, kD2 = kW0;
  // Cap on drag rate (1/2 rho Cd A/m |v_rel|) x kick length: each of a kick's two drag half-flows scales
  // v_rel by at most 1/(1 -+ 1/8); reached only far below the burn-up altitude (see drag.hpp).
  static constexpr double kDragRateLimitPerKick = 0.25;

  // Objects that start a step below this altitude (above the equatorial radius) take
  // kLowAltitudeSubsteps steps of dt / k. Drag grows steeply with depth, and so does the step's error:
  // an object whose perigee dips to ~210 km was ~40 m off after a day at dt = 10 s, enough to change a
  // conjunction's miss distance between dt = 10 and 5 s by 38 m. With 4 sub-steps the error falls by
  // 4^4 (4th order). Few objects fly this low (they burn up within weeks), so the cost is small.
  static constexpr double kLowAltitude_m = 300.0e3;
  static constexpr int kLowAltitudeSubsteps = 4;
  // Objects that took sub-steps in the last step() (population indices, ascending).
  const std::vector<std::uint32_t>& last_substepped() const { return low_; }
  // A low object's cost in a step beyond an ordinary one's, in ordinary steps (its sub-steps, and the
  // copies of its states): chunks are shared out by cost (thread_chunks.hpp, ChunkLayout). Only the
  // balance between the threads depends on it.
  static constexpr double kLowObjectExtraCost = 3.5;
  const ChunkLayout* last_chunks() const override { return &chunks_; }

  struct StepArrays;

 private:
  ForceModel model_;
  Integrator integrator_;
  Composition composition_;
  int threads_ = 0;
  TeamTimeline* timeline_ = nullptr;
  std::vector<std::uint32_t> low_;  // objects sub-stepped in this step
  std::vector<char> low_flag_;      // per object: starts this step low
  // Per thread, on its own cache line: the low objects of the blocks it took (in the order taken), with
  // copies of their states and area-to-mass ratios (x, y, z, vx, vy, vz, drag, SRP).
  struct alignas(64) ThreadLow {
    std::vector<std::uint32_t> index;
    std::array<std::vector<double>, 8> state;
    void clear();
    // Flags objects [begin, end) that start the step below low_radius2 (squared radius) and copies them.
    void copy_low(const Population& population, char* flag, std::size_t begin, std::size_t end,
                  double low_radius2);
    StepArrays arrays();
  };
  std::vector<ThreadLow> low_by_thread_;
  ChunkLayout chunks_;  // the step's chunks: of equal cost, from the last step's low objects
  ChunkBlocks blocks_;  // the chunks handed out in blocks (thread_chunks.hpp)
};

// Throws std::invalid_argument with Population::validate's message ("object <id>: <field> <reason>")
// when an object cannot be propagated.
void validate_for_propagation(const Population& population);

}  // namespace kessler
