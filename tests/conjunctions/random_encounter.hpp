// Random meeting places for the filter tests: a point of a spherical shell and the gravity there.
#pragma once

#include <cmath>
#include <random>

namespace kessler::testing {

struct MeetingPoint {
  double position_m[3];
  double gravity_m_s2[3];  // GM / r^2 towards the centre
};

// A point of the sphere of radius_m (a uniform sample of the cube [-1, 1]^3, normalised: three draws).
inline MeetingPoint random_meeting_point(std::mt19937_64& rng, double radius_m) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  MeetingPoint point;
  double n = 0.0;
  for (double& x : point.position_m) {
    x = u(rng);
    n += x * x;
  }
  const double g = 3.986004418e14 / (radius_m * radius_m);
  for (int k = 0; k < 3; ++k) {
    point.position_m[k] *= radius_m / std::sqrt(n);
    point.gravity_m_s2[k] = -g * point.position_m[k] / radius_m;
  }
  return point;
}

}  // namespace kessler::testing
