// The symplectic compositions (Yoshida, Blanes-Moan) against analytic solutions: two-body order of
// convergence, long-term energy and angular momentum, and the J2 secular nodal regression.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/integration/burn_up.hpp"
#include "core/integration/symplectic_propagator.hpp"
#include "core/physics/drag.hpp"
#include "core/physics/gravity.hpp"
#include "tests/physics/two_body.hpp"

namespace kessler {
namespace {

using testing::kMu;
constexpr double kDeg = std::numbers::pi / 180.0;

Population one_object(const Eigen::Vector3d& r, const Eigen::Vector3d& v) {
  ObjectRecord rec;
  rec.id = 1;
  rec.position_m = r;
  rec.velocity_m_s = v;
  rec.radius_m = 0.5;
  rec.mass_kg = 100;
  rec.drag_area_to_mass_m2_kg = 0.01;
  rec.srp_area_to_mass_m2_kg = 0.005;
  Population p;
  p.add(rec);
  return p;
}

ForceModelSettings only(bool j2) {
  ForceModelSettings s;
  s.j2 = j2;
  s.c22_s22 = s.drag = s.srp = false;
  return s;
}

const UtcEpoch kEpoch = UtcEpoch::from_calendar(2022, 3, 1, 0, 0, 0);

TEST(Yoshida, CoefficientsAreYoshidasFourthOrderSet) {
  const double cbrt2 = std::cbrt(2.0);
  EXPECT_NEAR(SymplecticPropagator::kW1, 1.0 / (2.0 - cbrt2), 1e-15);
  EXPECT_NEAR(SymplecticPropagator::kW0, -cbrt2 / (2.0 - cbrt2), 1e-15);
  EXPECT_NEAR(2 * SymplecticPropagator::kC1 + 2 * SymplecticPropagator::kC2, 1.0, 1e-15);
  EXPECT_NEAR(2 * SymplecticPropagator::kD1 + SymplecticPropagator::kD2, 1.0, 1e-15);
}

double fitted_slope(const std::vector<double>& dts, const std::vector<double>& errors) {
  double mx = 0, my = 0;
  const double n = static_cast<double>(dts.size());
  for (std::size_t i = 0; i < dts.size(); ++i) mx += std::log(dts[i]) / n, my += std::log(errors[i]) / n;
  double sxy = 0, sxx = 0;
  for (std::size_t i = 0; i < dts.size(); ++i) {
    const double dx = std::log(dts[i]) - mx;
    sxy += dx * (std::log(errors[i]) - my);
    sxx += dx * dx;
  }
  return sxy / sxx;
}

// The object's position after span_s in whole steps of dt.
Eigen::Vector3d position_after(SymplecticPropagator& propagator, Population p, double span_s, double dt) {
  const int steps = static_cast<int>(std::lround(span_s / dt));
  for (int s = 0; s < steps; ++s) propagator.step(p, s * dt, dt);
  return p.state.position(0);
}

// The drag tests' object: perigee 191 km, e = 0.088, Cd A/m = 0.40 m^2/kg (as leo-19647 object 14524),
// followed for kLowPerigeeSpan_s.
constexpr double kLowPerigeeSpan_s = 14000.0;
Population low_perigee_object() {
  Eigen::Vector3d r0, v0;
  const double e = 0.088, a = (6378137.0 + 191e3) / (1.0 - e);
  testing::state_from_elements(a, e, 51.6 * kDeg, 0.3, 1.1, 0.2, r0, v0);
  Population p = one_object(r0, v0);
  p.drag_area_to_mass_m2_kg[0] = 0.40;
  return p;
}

// dts: steps where the 4th-order term dominates (Blanes-Moan's error is ~10^4 times smaller, so its
// range starts higher, above rounding).
void check_kepler_order(Integrator integrator, const std::vector<double>& dts) {
  Eigen::Vector3d r0, v0;
  testing::state_from_elements(7500e3, 0.05, 51.6 * kDeg, 0.3, 1.1, 0.2, r0, v0);
  const Eigen::Vector3d exact = testing::kepler_position(r0, v0, 86400.0);
  SymplecticPropagator propagator(only(false), kEpoch, integrator);
  std::vector<double> errors;
  for (double dt : dts) {
    errors.push_back((position_after(propagator, one_object(r0, v0), 86400.0, dt) - exact).norm());
    std::printf("%s dt %4.0f s: position error after one day %.3e m\n", integrator_name(integrator).data(),
                dt, errors.back());
  }
  const double slope = fitted_slope(dts, errors);
  std::printf("fitted order %.3f\n", slope);
  EXPECT_GE(slope, 3.7);
  EXPECT_LE(slope, 4.3);
}

TEST(Yoshida, KeplerErrorFallsWithFourthOrder) {
  check_kepler_order(Integrator::kYoshida4, {5, 10, 20, 40});
}
TEST(BlanesMoan, KeplerErrorFallsWithFourthOrder) {
  check_kepler_order(Integrator::kBlanesMoan4, {10, 20, 40, 80});
}

// The orbital phase error that decides whether conjunctions depend on the step: a circular 540 km orbit
// (as leo-19647 object 16248, whose 7 m at dt = 10 s moved one miss distance by 5.7 m between dt 10
// and 5 s) after 22 h, against the analytic two-body solution. Yoshida at 10 s against Blanes-Moan at
// 30 s, which costs 7/9 of the force evaluations.
TEST(BlanesMoan, ThirtySecondStepsBeatYoshidasTenByTwoOrders) {
  Eigen::Vector3d r0, v0;
  testing::state_from_elements(6378137.0 + 540e3, 0.0, 0.9, 0.3, 1.1, 0.2, r0, v0);
  const double span_s = 22 * 3600.0;
  const Eigen::Vector3d exact = testing::kepler_position(r0, v0, span_s);
  auto error_after = [&](Integrator integrator, double dt) {
    SymplecticPropagator propagator(only(false), kEpoch, integrator);
    return (position_after(propagator, one_object(r0, v0), span_s, dt) - exact).norm();
  };
  const double yoshida_10 = error_after(Integrator::kYoshida4, 10.0);
  const double blanes_moan_30 = error_after(Integrator::kBlanesMoan4, 30.0);
  std::printf("circular 540 km, 22 h: yoshida4 at 10 s %.3f m, blanes_moan4 at 30 s %.4f m\n", yoshida_10,
              blanes_moan_30);
  EXPECT_GT(yoshida_10, 5.0);  // the error the step-independence check tripped on
  EXPECT_LT(blanes_moan_30, 0.1);
  EXPECT_LT(blanes_moan_30 * 50.0, yoshida_10);
}

// The full gravity field (J2 and the rotating C22/S22) keeps the order: self-convergence against a 0.5 s
// solution (the analytic two-body check above is the reference for the integrator itself). The sub-step
// times are pinned separately (Determinism.ForceModelAccelerationEqualsThePropagatorsKernel).
void check_time_dependent_field_order(Integrator integrator, const std::vector<double>& dts) {
  ForceModelSettings gravity_field;
  gravity_field.drag = gravity_field.srp = false;
  Eigen::Vector3d r0, v0;
  testing::state_from_elements(6900e3, 0.01, 51.6 * kDeg, 0.3, 1.1, 0.2, r0, v0);
  SymplecticPropagator propagator(gravity_field, kEpoch, integrator);
  auto run = [&](double dt) { return position_after(propagator, one_object(r0, v0), 21600.0, dt); };
  const Eigen::Vector3d reference = run(0.5);
  std::vector<double> errors;
  for (double dt : dts) errors.push_back((run(dt) - reference).norm());
  const double slope = fitted_slope(dts, errors);
  std::printf("%s, J2 + C22/S22, 6 h: errors %.2e %.2e %.2e %.2e m, order %.3f\n",
              integrator_name(integrator).data(), errors[0], errors[1], errors[2], errors[3], slope);
  EXPECT_GE(slope, 3.7);
  EXPECT_LE(slope, 4.3);
}

TEST(Yoshida, TimeDependentFieldKeepsFourthOrder) {
  check_time_dependent_field_order(Integrator::kYoshida4, {10, 20, 40, 60});
}
TEST(BlanesMoan, TimeDependentFieldKeepsFourthOrder) {
  check_time_dependent_field_order(Integrator::kBlanesMoan4, {20, 40, 60, 120});
}

// Drag is velocity-dependent; each kick splits it symmetrically around the conservative kick, which keeps
// the composed step 4th order. The low-perigee object, full force model, 14,000 s: self-convergence
// against a dt = 0.5 s solution.
// (With drag taken at the velocity before each kick the errors were 30 / 88 / 199 / 329 m: first order.)
void check_low_perigee_drag_order(Integrator integrator, const std::vector<double>& dts,
                                  double max_error_at_10_m) {
  SymplecticPropagator propagator(ForceModelSettings{}, kEpoch, integrator);
  auto run = [&](double dt) {
    return position_after(propagator, low_perigee_object(), kLowPerigeeSpan_s, dt);
  };
  const Eigen::Vector3d reference = run(0.5);
  // Drag matters here: without it the object ends far from where it does with it.
  ForceModelSettings no_drag;
  no_drag.drag = false;
  SymplecticPropagator drag_free(no_drag, kEpoch);
  EXPECT_GT((position_after(drag_free, low_perigee_object(), kLowPerigeeSpan_s, 10.0) - reference).norm(),
            1e3);
  std::vector<double> errors;
  for (double dt : dts) errors.push_back((run(dt) - reference).norm());
  const double slope = fitted_slope(dts, errors);
  std::printf(
      "%s, drag, perigee 191 km, 14,000 s: errors %.3g %.3g %.3g %.3g m at dt %g/%g/%g/%g s, order %.3f\n",
      integrator_name(integrator).data(), errors[0], errors[1], errors[2], errors[3], dts[0], dts[1], dts[2],
      dts[3], slope);
  EXPECT_GE(slope, 3.5);
  EXPECT_LE(slope, 4.5);
  EXPECT_LT((run(10.0) - reference).norm(), max_error_at_10_m);
}

// dt 10 s: Yoshida was 200 m off for leo-19647 object 14524 before the low objects' sub-steps.
TEST(Yoshida, LowPerigeeDragKeepsFourthOrder) {
  check_low_perigee_drag_order(Integrator::kYoshida4, {2.5, 5, 10, 20}, 10.0);
}
// Blanes-Moan's own error is so small here (millimetres at 10 s) that other effects of the same size
// set the measured order: the density table's kinks (a piecewise exponential: the drag's slope jumps at
// each layer boundary) and the switch to sub-steps below 300 km, which falls on different orbit
// positions for each step. (Measured: order 2.8 with the table, 1.8 with the smooth fit, over 10..50 s.)
// So for this orbit the test is the error itself, against Yoshida's.
TEST(BlanesMoan, LowPerigeeDragWithTheDensityTableIsCentimetresAtTenSeconds) {
  auto run = [&](Integrator integrator, double dt) {
    SymplecticPropagator propagator(ForceModelSettings{}, kEpoch, integrator);
    return position_after(propagator, low_perigee_object(), kLowPerigeeSpan_s, dt);
  };
  const Eigen::Vector3d reference = run(Integrator::kBlanesMoan4, 0.5);
  const double yoshida_10 = (run(Integrator::kYoshida4, 10.0) - reference).norm();
  const double blanes_moan_10 = (run(Integrator::kBlanesMoan4, 10.0) - reference).norm();
  const double blanes_moan_35 = (run(Integrator::kBlanesMoan4, 35.0) - reference).norm();
  std::printf("density table, perigee 191 km: yoshida4 10 s %.3g m, blanes_moan4 10 s %.3g m, 35 s %.3g m\n",
              yoshida_10, blanes_moan_10, blanes_moan_35);
  EXPECT_LT(blanes_moan_10, 0.02);
  EXPECT_LT(blanes_moan_35, 1.0);
  EXPECT_LT(blanes_moan_35, yoshida_10);
}

// Drag at the step's ends (DragCoupling::kStepEnds) is a Strang splitting of drag around the conservative
// step: 2nd order in drag, an error that is a small fraction of drag's own effect. The low-perigee object
// (the worst case: drag 10^2-10^4 times stronger than for the population above 300 km), against a dt =
// 0.5 s solution with drag at every kick (4th order, converged to millimetres).
TEST(BlanesMoan, DragAtTheStepsEndsIsSecondOrderAndAFractionOfDragsEffect) {
  ForceModelSettings ends;
  ends.drag_coupling = DragCoupling::kStepEnds;
  SymplecticPropagator every_kick(ForceModelSettings{}, kEpoch), at_ends(ends, kEpoch);
  const Eigen::Vector3d reference = position_after(every_kick, low_perigee_object(), kLowPerigeeSpan_s, 0.5);
  ForceModelSettings no_drag;
  no_drag.drag = false;
  SymplecticPropagator drag_free(no_drag, kEpoch);
  const double drag_effect =
      (position_after(drag_free, low_perigee_object(), kLowPerigeeSpan_s, 0.5) - reference).norm();
  const std::vector<double> dts = {5.0, 10.0, 20.0, 40.0};
  std::vector<double> errors;
  for (double dt : dts)
    errors.push_back(
        (position_after(at_ends, low_perigee_object(), kLowPerigeeSpan_s, dt) - reference).norm());
  const double slope = fitted_slope(dts, errors);
  std::printf(
      "drag at the step's ends, perigee 191 km, 14,000 s: errors %.3g %.3g %.3g %.3g m at dt 5/10/20/40 s, "
      "order %.3f; drag's effect %.4g m\n",
      errors[0], errors[1], errors[2], errors[3], slope, drag_effect);
  EXPECT_GE(slope, 1.6);
  EXPECT_LE(slope, 2.5);
  // At 35 s (a whole number of steps in the span, above the default 30 s), under 1e-3 of drag's effect
  // (the density alone is uncertain by 10-30 %).
  const double at_35 =
      (position_after(at_ends, low_perigee_object(), kLowPerigeeSpan_s, 35.0) - reference).norm();
  EXPECT_LT(at_35, 1e-3 * drag_effect);
  EXPECT_GT(at_35, 1.0);  // and the splitting's error is there to see
}

// A 400 km circular orbit for a day at 30 s: the two couplings agree to a small fraction of drag's effect.
TEST(BlanesMoan, DragAtTheStepsEndsAgreesWithEveryKickAt400KmOverADay) {
  Eigen::Vector3d r0, v0;
  testing::state_from_elements(6778137.0, 0.0005, 51.6 * kDeg, 0.3, 1.1, 0.2, r0, v0);
  ForceModelSettings ends, no_drag;
  ends.drag_coupling = DragCoupling::kStepEnds;
  no_drag.drag = false;
  SymplecticPropagator every_kick(ForceModelSettings{}, kEpoch), at_ends(ends, kEpoch),
      drag_free(no_drag, kEpoch);
  const Eigen::Vector3d every = position_after(every_kick, one_object(r0, v0), 86400.0, 30.0);
  const double drag_effect = (position_after(drag_free, one_object(r0, v0), 86400.0, 30.0) - every).norm();
  const double difference = (position_after(at_ends, one_object(r0, v0), 86400.0, 30.0) - every).norm();
  std::printf("400 km, a day at 30 s: step ends vs every kick %.3g m, drag's effect %.4g m\n", difference,
              drag_effect);
  EXPECT_GT(drag_effect, 100.0);
  EXPECT_LT(difference, 1e-3 * drag_effect);
}

// step_keeping_start copies the start states in the same pass: the copy is the state before the step and
// the step is the plain step's, bit for bit (a low object sub-stepped among them too).
TEST(Yoshida, StepKeepingStartCopiesTheStartAndStepsAsUsual) {
  Population a;
  for (int k = 0; k < 2000; ++k) {
    Eigen::Vector3d r, v;
    const double perigee_m = k == 7 ? 200e3 : 450e3 + 300.0 * k;
    testing::state_from_elements(6378137.0 + perigee_m, 0.0005 * (k % 7), 0.3 + 0.001 * k, 0.01 * k, 0.2,
                                 0.003 * k, r, v);
    Population one = one_object(r, v);
    one.id[0] = 1 + k;
    a.add(one.record(0));
  }
  Population b = a;
  SymplecticPropagator plain(ForceModelSettings{}, kEpoch), keeping(ForceModelSettings{}, kEpoch);
  plain.set_threads(2);
  keeping.set_threads(2);
  StateArrays start;
  for (int s = 0; s < 20; ++s) {
    const StateArrays before = b.state;
    plain.step(a, s * 10.0, 10.0);
    keeping.step_keeping_start(b, s * 10.0, 10.0, start);
    ASSERT_EQ(start.size(), before.size());
    EXPECT_EQ(start.x, before.x);
    EXPECT_EQ(start.vz, before.vz);
    EXPECT_EQ(a.state.x, b.state.x);
    EXPECT_EQ(a.state.vy, b.state.vy);
  }
  EXPECT_EQ(keeping.last_substepped().size(), 1u);
}

// The burn-up flags set in the step's own pass are burns_up on the final end states: those of the
// low objects after their sub-steps too. A radius a hair outside and at a low object's end
// position (the next double above its squared radius, and that radius) tells its final state from the
// main pass's (a fraction of a millimetre apart); the other objects' flags match a
// scan of the end states, with 1 and 2 threads. The copies of the start and end states made in the same
// pass (StepRequest::start_out, end_out) are those states bit for bit.
TEST(Yoshida, BurnUpFlagsAndCopiesInTheStepAreThoseOfTheEndStates) {
  Population start;
  for (int k = 0; k < 3000; ++k) {
    Eigen::Vector3d r, v;
    // Every 100th object on an orbit whose perigee (120-140 km) lies below the burn-up altitude, some
    // of them descending through it in these steps; object 7 low (200 km at perigee) and sub-stepped.
    const bool decaying = k % 100 == 3;
    const double perigee_m = k == 7 ? 200e3 : decaying ? 120e3 + 200.0 * (k / 100) : 450e3 + 300.0 * k;
    const double e = decaying ? 0.02 : 0.0005 * (k % 7);
    const double anomaly = decaying ? -0.5 + 0.017 * (k / 100) : 0.003 * k;
    testing::state_from_elements((6378137.0 + perigee_m) / (1.0 - e), e, 0.3 + 0.001 * k, 0.01 * k, 0.2,
                                 anomaly, r, v);
    Population one = one_object(r, v);
    one.id[0] = 1 + k;
    one.drag_area_to_mass_m2_kg[0] = 0.02;
    start.add(one.record(0));
  }
  const double radius2_150km = burn_up_radius2(150e3);
  for (int threads : {1, 2}) {
    SymplecticPropagator plain(ForceModelSettings{}, kEpoch), flagging(ForceModelSettings{}, kEpoch);
    plain.set_threads(threads);
    flagging.set_threads(threads);
    Population a = start, b = start;
    std::vector<char> in_step, scanned;
    StateArrays start_states, end_states;
    std::size_t burning = 0;
    for (int s = 0; s < 30; ++s) {
      plain.step(a, s * 10.0, 10.0);
      const StateArrays before = b.state;
      flagging.step_with(b, s * 10.0, 10.0, StepRequest{&start_states, &in_step, radius2_150km, &end_states});
      ASSERT_EQ(a.state.x, b.state.x);
      // The copies of both ends, the low objects' end states included (written after their sub-steps).
      for (auto [copy, real] : {std::pair<const StateArrays*, const StateArrays*>{&start_states, &before},
                                std::pair<const StateArrays*, const StateArrays*>{&end_states, &b.state}}) {
        ASSERT_EQ(copy->x, real->x) << "step " << s;
        ASSERT_EQ(copy->y, real->y);
        ASSERT_EQ(copy->z, real->z);
        ASSERT_EQ(copy->vx, real->vx);
        ASSERT_EQ(copy->vy, real->vy);
        ASSERT_EQ(copy->vz, real->vz);
      }
      flag_burn_ups(a.state, radius2_150km, scanned);
      ASSERT_EQ(in_step, scanned) << "step " << s;
      for (char f : in_step) burning += f != 0;
    }
    EXPECT_GT(burning, 10u);
    // Object 7, sub-stepped in the first step: radii a hair outside and at its end position.
    Population c = start, d = start;
    plain.step(c, 0.0, 10.0);
    const double r2 = c.state.x[7] * c.state.x[7] + c.state.y[7] * c.state.y[7] + c.state.z[7] * c.state.z[7];
    flagging.step_with(d, 0.0, 10.0, StepRequest{nullptr, &in_step, std::nextafter(r2, 2.0 * r2)});
    const auto& low = flagging.last_substepped();
    ASSERT_NE(std::find(low.begin(), low.end(), 7u), low.end());
    EXPECT_EQ(in_step[7], 1);
    d = start;
    flagging.step_with(d, 0.0, 10.0, StepRequest{nullptr, &in_step, r2});
    EXPECT_EQ(in_step[7], 0);
  }
}

// Objects below 300 km take four sub-steps. The choice and the result depend on the object alone: the
// same bits alone or among 3,000 higher objects, with 1 or 2 threads, and only low objects are chosen.
TEST(Yoshida, LowObjectsTakeSubstepsWhateverTheirCompany) {
  Eigen::Vector3d r_low, v_low;
  const double e = 0.088, a = (6378137.0 + 191e3) / (1.0 - e);
  testing::state_from_elements(a, e, 51.6 * kDeg, 0.3, 1.1, 0.0, r_low, v_low);  // at perigee
  Population alone = one_object(r_low, v_low);
  alone.drag_area_to_mass_m2_kg[0] = 0.40;
  Population crowd;
  for (int k = 0; k < 3000; ++k) {
    Eigen::Vector3d r, v;
    testing::state_from_elements(6378137.0 + 500e3 + k, 0.001, 0.9, 0.01 * k, 0.0, 0.002 * k, r, v);
    Population one = one_object(r, v);
    one.id[0] = 1000 + k;
    crowd.add(one.record(0));
  }
  crowd.add(alone.record(0));
  const std::size_t low_index = crowd.size() - 1;
  SymplecticPropagator single(ForceModelSettings{}, kEpoch), team(ForceModelSettings{}, kEpoch);
  single.set_threads(1);
  team.set_threads(2);
  std::size_t substepped_steps = 0;
  for (int s = 0; s < 600; ++s) {
    single.step(alone, s * 10.0, 10.0);
    team.step(crowd, s * 10.0, 10.0);
    const auto& chosen = team.last_substepped();
    ASSERT_LE(chosen.size(), 1u);
    if (!chosen.empty()) {
      EXPECT_EQ(chosen[0], low_index);
      ++substepped_steps;
    }
    EXPECT_EQ(single.last_substepped().size(), chosen.size());
  }
  // Perigee at 191 km, apogee near 1,400 km: a part of each orbit is below 300 km, most is not.
  EXPECT_GT(substepped_steps, 20u);
  EXPECT_LT(substepped_steps, 300u);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(alone.state.position(0)[k], crowd.state.position(low_index)[k]);
    EXPECT_EQ(alone.state.velocity(0)[k], crowd.state.velocity(low_index)[k]);
  }
}

// Low objects cluster in a catalog (one breakup's decaying debris sits together), so the chunk that holds
// them costs more, and other threads take some of its blocks (thread_chunks.hpp, ChunkBlocks): the states
// must not depend on the team, bit for bit, nor on which thread propagated or sub-stepped an object, and
// the list of sub-stepped objects is in population order on any team.
TEST(Yoshida, SharedOutSubstepsGiveTheSameBitsOnAnyTeam) {
  Population crowd;
  for (int k = 0; k < 3000; ++k) {
    Eigen::Vector3d r, v;
    // The first 400 objects dip below 300 km (perigee 200-240 km, eccentric); the rest circle at 500 km.
    if (k < 400) {
      const double e = 0.05, a = (6378137.0 + 200e3 + 100.0 * k) / (1.0 - e);
      testing::state_from_elements(a, e, 0.9, 0.01 * k, 0.3, 0.0, r, v);
    } else {
      testing::state_from_elements(6378137.0 + 500e3 + k, 0.001, 0.9, 0.01 * k, 0.0, 0.002 * k, r, v);
    }
    Population one = one_object(r, v);
    one.id[0] = 1000 + k;
    one.drag_area_to_mass_m2_kg[0] = 0.02;
    crowd.add(one.record(0));
  }
  std::vector<Population> runs;
  std::vector<std::vector<std::uint32_t>> substepped;
  std::size_t substeps = 0;
  for (int threads : {1, 2, 3, 7}) {
    Population p = crowd;
    SymplecticPropagator propagator(ForceModelSettings{}, kEpoch);
    propagator.set_threads(threads);
    for (int s = 0; s < 60; ++s) {
      propagator.step(p, s * 10.0, 10.0);
      if (threads == 1) substeps += propagator.last_substepped().size();
    }
    runs.push_back(p);
    substepped.push_back(propagator.last_substepped());
  }
  for (std::size_t r = 1; r < substepped.size(); ++r) EXPECT_EQ(substepped[0], substepped[r]);
  EXPECT_GT(substeps, 60u * 100u);  // most of the 400 are low at any step
  for (std::size_t r = 1; r < runs.size(); ++r)
    for (std::size_t i = 0; i < crowd.size(); ++i)
      for (int k = 0; k < 3; ++k) {
        ASSERT_EQ(runs[0].state.position(i)[k], runs[r].state.position(i)[k]) << "object " << i;
        ASSERT_EQ(runs[0].state.velocity(i)[k], runs[r].state.velocity(i)[k]) << "object " << i;
      }
}

// The drag sub-flow against its closed form, and its time symmetry (negative h undoes positive h), which
// is what makes each kick symmetric.
TEST(Yoshida, DragFlowIsTheExactSolutionAndReversible) {
  const double rho = 3.725e-12 * 1e3, cda = 0.4, x = 6778e3, y = 1000e3, h = 13.5;
  const double w = constants::kEarthRotationRate_rad_s;
  const Eigen::Vector3d v0(-900.0, 7600.0, 300.0);
  const Eigen::Vector3d rel0(v0.x() + w * y, v0.y() - w * x, v0.z());
  double vx = v0.x(), vy = v0.y(), vz = v0.z();
  drag_flow(rho, cda, std::numeric_limits<double>::infinity(), x, y, h, vx, vy, vz);
  const Eigen::Vector3d rel_exact = rel0 / (1.0 + 0.5 * rho * cda * rel0.norm() * h);
  const Eigen::Vector3d rel(vx + w * y, vy - w * x, vz);
  EXPECT_LT((rel - rel_exact).norm(), 1e-12 * rel0.norm());
  EXPECT_LT(rel.norm(), rel0.norm());
  // v_rel' = -k |v_rel| v_rel checked by a central difference of the flow in h.
  auto flow = [&](double hh) {
    double a = v0.x(), b = v0.y(), c = v0.z();
    drag_flow(rho, cda, std::numeric_limits<double>::infinity(), x, y, hh, a, b, c);
    return Eigen::Vector3d(a, b, c);
  };
  const Eigen::Vector3d derivative = (flow(1e-2) - flow(-1e-2)) / 2e-2;
  EXPECT_LT((derivative + 0.5 * rho * cda * rel0.norm() * rel0).norm(),
            1e-6 * (0.5 * rho * cda * rel0.squaredNorm()));
  drag_flow(rho, cda, std::numeric_limits<double>::infinity(), x, y, -h, vx, vy, vz);
  EXPECT_LT((Eigen::Vector3d(vx, vy, vz) - v0).norm(), 1e-11 * v0.norm());
  // The whole kick: kick(-h) after kick(h) returns the velocity.
  const ForceModel model(ForceModelSettings{}, kEpoch);
  const Eigen::Vector3d r(6578e3, 0.0, 0.0), v(0.0, 7800.0, 0.0);
  const ObjectForceProperties props{0.4, 0.01};
  const Eigen::Vector3d there = model.kick(r, v, 0.0, h, props);
  EXPECT_GT((there - v).norm(), 1e-3);
  EXPECT_LT((model.kick(r, there, 0.0, -h, props) - v).norm(), 1e-10 * v.norm());
}

TEST(Yoshida, EnergyBoundedAndAngularMomentumConservedOver1000Orbits) {
  Eigen::Vector3d r0, v0;
  const double a = 7000e3;
  testing::state_from_elements(a, 0.05, 51.6 * kDeg, 0.3, 1.1, 0.0, r0, v0);
  const double period = 2 * std::numbers::pi * std::sqrt(a * a * a / kMu);
  const double dt = 10.0;
  const long steps = static_cast<long>(1000 * period / dt);
  const long per_100_orbits = static_cast<long>(100 * period / dt);
  Population p = one_object(r0, v0);
  const double e0 = 0.5 * v0.squaredNorm() - kMu / r0.norm();
  const Eigen::Vector3d h0 = r0.cross(v0);
  SymplecticPropagator propagator(only(false), kEpoch);
  double max_first = 0, max_last = 0, max_h = 0;
  for (long s = 0; s < steps; ++s) {
    propagator.step(p, s * dt, dt);
    const Eigen::Vector3d r = p.state.position(0), v = p.state.velocity(0);
    const double de = std::abs((0.5 * v.squaredNorm() - kMu / r.norm() - e0) / e0);
    if (s < per_100_orbits) max_first = std::max(max_first, de);
    if (s >= steps - per_100_orbits) max_last = std::max(max_last, de);
    if (s % 100 == 0 || s == steps - 1) max_h = std::max(max_h, (r.cross(v) - h0).norm() / h0.norm());
  }
  std::printf("energy error: max first 100 orbits %.3e, last 100 %.3e; angular momentum %.3e\n", max_first,
              max_last, max_h);
  EXPECT_LE(max_last, 2 * max_first);
  EXPECT_LT(max_last, 1e-7);
  EXPECT_LT(max_h, 1e-10);
}

TEST(Yoshida, J2NodalRegressionMatchesTheSecularRate) {
  const double a = constants::kEarthEquatorialRadius_m + 700e3, inc = 98.19 * kDeg;
  Eigen::Vector3d r0, v0;
  testing::state_from_elements(a, 0.0, inc, 0.0, 0.0, 0.0, r0, v0);
  Population p = one_object(r0, v0);
  SymplecticPropagator propagator(only(true), kEpoch);
  const double dt = 10.0;
  const long steps = 10 * 8640;
  // Least-squares line through the node longitude sampled every minute (unwrapped).
  double st = 0, sy = 0, stt = 0, sty = 0, n = 0, previous = 0, offset = 0;
  for (long s = 0; s <= steps; ++s) {
    if (s % 6 == 0) {
      const Eigen::Vector3d h = p.state.position(0).cross(p.state.velocity(0));
      double node = std::atan2(h.x(), -h.y());
      if (s > 0 && node + offset - previous < -std::numbers::pi) offset += 2 * std::numbers::pi;
      if (s > 0 && node + offset - previous > std::numbers::pi) offset -= 2 * std::numbers::pi;
      node += offset;
      previous = node;
      const double t_day = s * dt / 86400.0;
      st += t_day, sy += node, stt += t_day * t_day, sty += t_day * node, n += 1;
    }
    if (s < steps) propagator.step(p, s * dt, dt);
  }
  const double rate_deg_day = (n * sty - st * sy) / (n * stt - st * st) / kDeg;
  // Secular rate: dOmega/dt = -3/2 n J2 (R/p)^2 cos i (Vallado eq. 9-41).
  const double mean_motion = std::sqrt(kMu / (a * a * a));
  const double expected = -1.5 * mean_motion * gravity::kJ2 *
                          std::pow(constants::kEarthGravityRadius_m / a, 2) * std::cos(inc) * 86400.0 / kDeg;
  std::printf("nodal rate: integrated %.5f deg/day, analytic %.5f deg/day\n", rate_deg_day, expected);
  EXPECT_NEAR(expected, 0.9856, 0.01);
  EXPECT_NEAR(rate_deg_day, expected, 0.01 * std::abs(expected));
}

}  // namespace
}  // namespace kessler
