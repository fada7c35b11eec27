// The web tests' run: pairs of objects on circular Kepler orbits (every other force off) aimed to pass
// each other at set miss distances, so the run has conjunctions at known kappas, and one object falling
// through the burn-up altitude (a re-entry to mark).
#pragma once

#include <cmath>
#include <cstdio>
#include <string>

namespace kessler::test {

// radius 2 m each (r1 + r2 = 4 m); pair k passes at about kMissM[k] (the offset's part across the
// relative velocity), i.e. kappa about kMissM[k] / 4.
inline constexpr double kMissM[] = {3.0, 6.0, 15.0, 30.0, 500.0};

inline std::string crossings_scenario() {
  const double mu = 3.986004418e14, r = 7000e3, v = std::sqrt(mu / r), n = v / r;
  std::string table;
  auto add = [&](int id, const double u[3], const double w[3], double t) {
    // On the circle through u (unit position) moving along w (unit velocity), t seconds before u.
    const double c = std::cos(n * t), s = std::sin(n * t);
    char line[320];
    std::snprintf(line, sizeof line, "    %d,2022-01-01T00:00:00Z,%.6f,%.6f,%.6f,%.9f,%.9f,%.9f,2.0,100,\n",
                  id, r * (c * u[0] - s * w[0]), r * (c * u[1] - s * w[1]), r * (c * u[2] - s * w[2]),
                  v * (s * u[0] + c * w[0]), v * (s * u[1] + c * w[1]), v * (s * u[2] + c * w[2]));
    table += line;
  };
  for (int k = 0; k < 5; ++k) {
    const double phi = k * 70.0 * M_PI / 180.0, t = 60.0 + 60.0 * k;
    const double delta = 2.0 * kMissM[k] / r;  // B's meeting point lifted out of A's plane
    const double ua[3] = {std::cos(phi), std::sin(phi), 0}, wa[3] = {-std::sin(phi), std::cos(phi), 0};
    const double ub[3] = {std::cos(delta) * ua[0], std::cos(delta) * ua[1], std::sin(delta)};
    // B crosses A's track at 60 degrees, perpendicular to its own position.
    double wb[3] = {0.5 * wa[0], 0.5 * wa[1], 0.8660254037844386};
    const double dot = wb[0] * ub[0] + wb[1] * ub[1] + wb[2] * ub[2];
    for (int i = 0; i < 3; ++i) wb[i] -= dot * ub[i];
    const double norm = std::sqrt(wb[0] * wb[0] + wb[1] * wb[1] + wb[2] * wb[2]);
    for (double& x : wb) x /= norm;
    add(2 * k + 1, ua, wa, t);
    add(2 * k + 2, ub, wb, t);
  }
  // 155 km up, falling at 500 m/s: below the 150 km burn-up altitude after about 10 s.
  table += "    99,2022-01-01T00:00:00Z,0,0,6533137.0,0,0,-500.0,1.0,50,\n";
  return "name: web-crossings\nstart_epoch: \"2022-01-01T00:00:00Z\"\nduration_days: 0.005\ndt_s: 10\n"
         "force_model: {j2: false, c22_s22: false, drag: false, srp: false}\n"
         "progress_every_steps: 4\npopulation:\n  state_table: |\n" +
         table;
}

}  // namespace kessler::test
