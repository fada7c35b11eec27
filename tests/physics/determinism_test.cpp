// Thread independence and vector/scalar independence of the propagator on the leo-19647 population.
#include <gtest/gtest.h>

#include <cstring>

#include "core/catalog/leo19647.hpp"
#include "core/integration/burn_up.hpp"
#include "core/integration/symplectic_propagator.hpp"
#include "core/physics/gravity.hpp"

namespace kessler {
namespace {

Population first_objects(std::size_t n) {
  const Population all = load_leo19647(std::string(KESSLER_DATASETS_DIR) + "/leo-19647");
  Population p;
  for (std::size_t i = 0; i < n; ++i) p.add(all.record(i));
  return p;
}

bool bitwise_equal(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

ForceModelSettings with_coupling(DragCoupling coupling) {
  ForceModelSettings forces;
  forces.drag_coupling = coupling;
  return forces;
}

void propagate(Population& p, int threads, int steps, DragCoupling coupling = DragCoupling::kEveryKick) {
  SymplecticPropagator propagator(with_coupling(coupling), leo19647_epoch());
  propagator.set_threads(threads);
  for (int s = 0; s < steps; ++s) propagator.step(p, s * 10.0, 10.0);
}

void expect_one_and_two_threads_agree(DragCoupling coupling, int steps) {
  Population one = first_objects(5000), two = one;
  propagate(one, 1, steps, coupling);
  propagate(two, 2, steps, coupling);
  for (auto member : {&StateArrays::x, &StateArrays::y, &StateArrays::z, &StateArrays::vx, &StateArrays::vy,
                      &StateArrays::vz})
    EXPECT_TRUE(bitwise_equal(one.state.*member, two.state.*member));
  // The states moved (the test compares something).
  const Population start = first_objects(1);
  EXPECT_GT((one.state.position(0) - start.state.position(0)).norm(), 1e5);
}

TEST(Determinism, OneAndTwoThreadsGiveIdenticalBitsAfter1000StepsOf5000Objects) {
  expect_one_and_two_threads_agree(DragCoupling::kEveryKick, 1000);
}

TEST(Determinism, DragAtTheStepsEndsGivesIdenticalBitsOnOneAndTwoThreads) {
  expect_one_and_two_threads_agree(DragCoupling::kStepEnds, 500);
}

TEST(Leo19647Propagation, WholePopulationForAnHourWithBurnUps) {
  // As the simulation runs it: step, then remove objects below 150 km.
  Population p = first_objects(kLeo19647Objects);
  const Population start = p;
  SymplecticPropagator propagator(ForceModelSettings{}, leo19647_epoch());
  propagator.set_threads(1);  // threads are another test's subject; keep this one quick on a busy machine
  std::vector<char> flags;
  std::size_t burnt = 0;
  for (int s = 0; s < 360; ++s) {
    propagator.step(p, s * 10.0, 10.0);
    const auto events = find_burn_ups(p, 150e3, (s + 1) * 10.0, flags);
    for (const auto& e : events)
      ASSERT_GT(e.altitude_m, 100e3) << "object " << e.id << " fell far in one step";
    burnt += events.size();
    p.remove_flagged(flags);
  }
  std::printf("burn-ups in the first hour: %zu of %zu\n", burnt, start.size());
  EXPECT_LT(burnt, 20u);
  for (std::size_t i = 0; i < p.size(); ++i) {
    ASSERT_TRUE(p.state.position(i).allFinite() && p.state.velocity(i).allFinite()) << "object " << p.id[i];
    const std::size_t k = p.id[i] - 1;  // ids are 1..N in file order
    const double r0 = start.state.position(k).norm(), r = p.state.position(i).norm();
    // Energy per unit mass (with the J2 potential): drag only removes it (by up to ~1 % in an hour for the
    // population's lightest objects, Cd A/m up to 4.7 m^2/kg at 180 km); SRP and the rotating C22/S22
    // field move it by up to about 2e-5. A larger gain would mean an unstable integration.
    const double e0 = 0.5 * start.state.velocity(k).squaredNorm() - constants::kEarthMu_m3_s2 / r0 -
                      gravity::j2_potential(start.state.position(k));
    const double e1 = 0.5 * p.state.velocity(i).squaredNorm() - constants::kEarthMu_m3_s2 / r -
                      gravity::j2_potential(p.state.position(i));
    ASSERT_LT(e1 - e0, 1e-4 * std::abs(e0)) << "object " << p.id[i];
    ASSERT_LT(e0 - e1, 2e-2 * std::abs(e0)) << "object " << p.id[i];
  }
}

TEST(Leo19647Propagation, DeepAtmosphereStaysBoundedWithoutBurnUp) {
  // Cd A/m = 1 at 60 km: 1/2 rho (Cd A/m) |v| dt >> 1, where explicit kicks would explode; the drag cap
  // keeps the state bounded and slowing down.
  Population p;
  ObjectRecord r = first_objects(1).record(0);
  r.position_m = Eigen::Vector3d(constants::kEarthEquatorialRadius_m + 60e3, 0, 0);
  r.velocity_m_s = Eigen::Vector3d(0, 7800, 0);
  r.drag_area_to_mass_m2_kg = 1.0;
  p.add(r);
  SymplecticPropagator propagator(ForceModelSettings{}, leo19647_epoch());
  for (int s = 0; s < 30; ++s) {
    propagator.step(p, s * 10.0, 10.0);
    ASSERT_TRUE(p.state.velocity(0).allFinite());
    ASSERT_LT(p.state.velocity(0).norm(), 7900.0) << "step " << s;
    ASSERT_LT(p.state.position(0).norm(), constants::kEarthEquatorialRadius_m + 100e3) << "step " << s;
  }
}

TEST(Determinism, AnObjectAloneGivesTheSameBitsAsInsideTheVectorisedLoop) {
  // Alone, an object runs through the loop's scalar remainder; among 5000, through the SIMD body.
  for (DragCoupling coupling : {DragCoupling::kEveryKick, DragCoupling::kStepEnds}) {
    Population all = first_objects(5000);
    propagate(all, 1, 200, coupling);
    for (std::size_t i : {0ul, 1ul, 7ul, 4093ul, 4999ul}) {
      Population alone;
      alone.add(first_objects(5000).record(i));
      propagate(alone, 1, 200, coupling);
      EXPECT_EQ(std::memcmp(&alone.state.x[0], &all.state.x[i], sizeof(double)), 0) << i;
      EXPECT_EQ(std::memcmp(&alone.state.vz[0], &all.state.vz[i], sizeof(double)), 0) << i;
    }
  }
}

// One step by hand with ForceModel::kick, drift by drift and kick by kick from the composition's table,
// reproduces the propagator's vectorised kernel bit for bit (objects with drag), for both compositions.
void expect_kernel_is_the_composition(Integrator integrator) {
  const Population p0 = first_objects(3);
  Population p = p0;
  SymplecticPropagator propagator(ForceModelSettings{}, leo19647_epoch(), integrator);
  const double t0 = 100.0, dt = 10.0;
  propagator.step(p, t0, dt);
  const ForceModel& model = propagator.force_model();
  const Composition& c = composition_of(integrator);
  for (std::size_t i = 0; i < 3; ++i) {
    Eigen::Vector3d r = p0.state.position(i), v = p0.state.velocity(i);
    const ObjectForceProperties props{p0.drag_area_to_mass_m2_kg[i], p0.srp_area_to_mass_m2_kg[i]};
    EXPECT_GT(props.drag_area_to_mass_m2_kg, 0.0);
    for (std::size_t k = 0; k < static_cast<std::size_t>(c.kicks); ++k) {
      r += (c.drift[k] * dt) * v;
      v = model.kick(r, v, t0 + c.kick_time[k] * dt, c.kick[k] * dt, props);
    }
    r += (c.drift[static_cast<std::size_t>(c.kicks)] * dt) * v;
    EXPECT_EQ(r, p.state.position(i));
    EXPECT_EQ(v, p.state.velocity(i));
  }
}

TEST(Determinism, ForceModelKickEqualsThePropagatorsKernel) {
  expect_kernel_is_the_composition(Integrator::kYoshida4);
  expect_kernel_is_the_composition(Integrator::kBlanesMoan4);
}

// With drag at the step's ends: drag's flow over dt/2 at the start, the composition of drifts and
// conservative kicks, drag's flow over dt/2 at the end, by hand with ForceModel::drag_flow and
// conservative_kick, bit for bit.
void expect_step_ends_kernel_is_the_splitting(Integrator integrator) {
  const Population p0 = first_objects(3);
  Population p = p0;
  SymplecticPropagator propagator(with_coupling(DragCoupling::kStepEnds), leo19647_epoch(), integrator);
  const double t0 = 100.0, dt = 10.0;
  propagator.step(p, t0, dt);
  const ForceModel& model = propagator.force_model();
  const Composition& c = composition_of(integrator);
  for (std::size_t i = 0; i < 3; ++i) {
    Eigen::Vector3d r = p0.state.position(i), v = p0.state.velocity(i);
    const ObjectForceProperties props{p0.drag_area_to_mass_m2_kg[i], p0.srp_area_to_mass_m2_kg[i]};
    v = model.drag_flow(r, v, t0, 0.5 * dt, props);
    for (std::size_t k = 0; k < static_cast<std::size_t>(c.kicks); ++k) {
      r += (c.drift[k] * dt) * v;
      v = model.conservative_kick(r, v, t0 + c.kick_time[k] * dt, c.kick[k] * dt, props);
    }
    r += (c.drift[static_cast<std::size_t>(c.kicks)] * dt) * v;
    v = model.drag_flow(r, v, t0 + dt, 0.5 * dt, props);
    EXPECT_EQ(r, p.state.position(i));
    EXPECT_EQ(v, p.state.velocity(i));
  }
}

TEST(Determinism, DragAtTheStepsEndsIsTheSplittingByHand) {
  expect_step_ends_kernel_is_the_splitting(Integrator::kYoshida4);
  expect_step_ends_kernel_is_the_splitting(Integrator::kBlanesMoan4);
}

TEST(Determinism, WithoutDragBothCouplingsGiveTheSameBits) {
  // The drag flows add exactly zero without drag, so the two couplings differ only where drag acts.
  for (Integrator integrator : {Integrator::kYoshida4, Integrator::kBlanesMoan4}) {
    ForceModelSettings every = with_coupling(DragCoupling::kEveryKick),
                       ends = with_coupling(DragCoupling::kStepEnds);
    every.drag = ends.drag = false;
    Population a = first_objects(300), b = a;
    SymplecticPropagator pa(every, leo19647_epoch(), integrator), pb(ends, leo19647_epoch(), integrator);
    for (int s = 0; s < 20; ++s) {
      pa.step(a, s * 30.0, 30.0);
      pb.step(b, s * 30.0, 30.0);
    }
    EXPECT_TRUE(bitwise_equal(a.state.x, b.state.x) && bitwise_equal(a.state.vz, b.state.vz));
    // With drag they differ: the comparison above can fail.
    Population c = first_objects(300), d = c;
    SymplecticPropagator pc(with_coupling(DragCoupling::kEveryKick), leo19647_epoch(), integrator),
        pd(with_coupling(DragCoupling::kStepEnds), leo19647_epoch(), integrator);
    for (int s = 0; s < 20; ++s) {
      pc.step(c, s * 30.0, 30.0);
      pd.step(d, s * 30.0, 30.0);
    }
    EXPECT_FALSE(bitwise_equal(c.state.x, d.state.x));
  }
}

TEST(Determinism, YoshidasTableIsYoshidasScheme) {
  // The table's kick instants are the sums of the drifts before them, and Yoshida's are c1, dt/2, 1 - c1.
  for (const Composition* c : {&composition::kYoshida4, &composition::kBlanesMoan4}) {
    double elapsed = 0.0, kicks = 0.0;
    for (std::size_t k = 0; k < static_cast<std::size_t>(c->kicks); ++k) {
      elapsed += c->drift[k];
      EXPECT_NEAR(c->kick_time[k], elapsed, 1e-15);
      kicks += c->kick[k];
    }
    EXPECT_NEAR(elapsed + c->drift[static_cast<std::size_t>(c->kicks)], 1.0, 1e-15);
    EXPECT_NEAR(kicks, 1.0, 1e-15);
  }
  EXPECT_EQ(composition::kYoshida4.kick_time[0], SymplecticPropagator::kC1);
  EXPECT_EQ(composition::kYoshida4.kick_time[1], 0.5);
  EXPECT_EQ(composition::kYoshida4.kick_time[2], SymplecticPropagator::kC1 + 2 * SymplecticPropagator::kC2);
  EXPECT_EQ(composition::kYoshida4.kick[1], SymplecticPropagator::kD2);
}

TEST(Determinism, KickWithoutDragIsTheAccelerationKick) {
  // Without drag the kick is v + h a with a = ForceModel::acceleration, bit for bit (the drag half-flows
  // add exactly zero), so drag-free results are those of the plain drift-kick-drift scheme.
  ForceModelSettings no_drag;
  no_drag.drag = false;
  const ForceModel model(no_drag, leo19647_epoch());
  const Population p0 = first_objects(3);
  for (std::size_t i = 0; i < 3; ++i) {
    const ObjectForceProperties props{p0.drag_area_to_mass_m2_kg[i], p0.srp_area_to_mass_m2_kg[i]};
    const Eigen::Vector3d r = p0.state.position(i), v = p0.state.velocity(i);
    const double h = SymplecticPropagator::kD2 * 10.0;
    EXPECT_EQ(model.kick(r, v, 50.0, h, props), (v + h * model.acceleration(r, v, 50.0, props)).eval());
  }
}

}  // namespace
}  // namespace kessler
