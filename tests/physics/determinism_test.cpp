// Thread independence and vector/scalar independence of the propagator on the leo-19647 population.
#include <gtest/gtest.h>

#include <cstring>

#include "core/integration/yoshida_propagator.hpp"
#include "core/population/leo19647.hpp"

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

void propagate(Population& p, int threads, int steps) {
  YoshidaPropagator propagator(ForceModelSettings{}, leo19647_epoch());
  propagator.set_threads(threads);
  for (int s = 0; s < steps; ++s) propagator.step(p, s * 10.0, 10.0);
}

TEST(Determinism, OneAndTwoThreadsGiveIdenticalBitsAfter1000StepsOf5000Objects) {
  Population one = first_objects(5000), two = one;
  propagate(one, 1, 1000);
  propagate(two, 2, 1000);
  for (auto member : {&StateArrays::x, &StateArrays::y, &StateArrays::z, &StateArrays::vx, &StateArrays::vy,
                      &StateArrays::vz})
    EXPECT_TRUE(bitwise_equal(one.state.*member, two.state.*member));
  // The states moved (the test compares something).
  const Population start = first_objects(1);
  EXPECT_GT((one.state.position(0) - start.state.position(0)).norm(), 1e5);
}

TEST(Determinism, AnObjectAloneGivesTheSameBitsAsInsideTheVectorisedLoop) {
  // Alone, an object runs through the loop's scalar remainder; among 5000, through the SIMD body.
  Population all = first_objects(5000);
  propagate(all, 1, 200);
  for (std::size_t i : {0ul, 1ul, 7ul, 4093ul, 4999ul}) {
    Population alone;
    alone.add(first_objects(5000).record(i));
    propagate(alone, 1, 200);
    EXPECT_EQ(std::memcmp(&alone.state.x[0], &all.state.x[i], sizeof(double)), 0) << i;
    EXPECT_EQ(std::memcmp(&alone.state.vz[0], &all.state.vz[i], sizeof(double)), 0) << i;
  }
}

TEST(Determinism, ForceModelAccelerationEqualsThePropagatorsKernel) {
  // One Yoshida step by hand with ForceModel::acceleration reproduces the propagator's bits.
  const Population p0 = first_objects(3);
  Population p = p0;
  YoshidaPropagator propagator(ForceModelSettings{}, leo19647_epoch());
  propagator.step(p, 100.0, 10.0);
  const ForceModel& model = propagator.force_model();
  const double dt = 10.0, c1 = YoshidaPropagator::kC1 * dt, c2 = YoshidaPropagator::kC2 * dt;
  const double d1 = YoshidaPropagator::kD1 * dt, d2 = YoshidaPropagator::kD2 * dt;
  for (std::size_t i = 0; i < 3; ++i) {
    Eigen::Vector3d r = p0.state.position(i), v = p0.state.velocity(i);
    const ObjectForceProperties props{p0.drag_area_to_mass_m2_kg[i], p0.srp_area_to_mass_m2_kg[i]};
    r += c1 * v;
    v += d1 * model.acceleration(r, v, 100.0 + YoshidaPropagator::kC1 * dt, props);
    r += c2 * v;
    v += d2 * model.acceleration(r, v, 100.0 + 0.5 * dt, props);
    r += c2 * v;
    v += d1 *
         model.acceleration(r, v, 100.0 + (YoshidaPropagator::kC1 + 2 * YoshidaPropagator::kC2) * dt, props);
    r += c1 * v;
    EXPECT_EQ(r, p.state.position(i));
    EXPECT_EQ(v, p.state.velocity(i));
  }
}

}  // namespace
}  // namespace kessler
