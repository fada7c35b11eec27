// Symmetric compositions of drift (x += a dt v) and kick (v += b dt a(x, t)) that the symplectic
// propagator runs. Each is 4th order, time-symmetric, and evaluates the force once per kick.
//
//   yoshida4     Yoshida (1990, Phys. Lett. A 150, eq. 4.4-4.6): the paper's integrator. Three kicks,
//                the triple jump with a middle weight of -1.70, whose large error constant shows as
//                a drift of the orbital phase: 7.2 m after 22 h for a circular 540 km orbit at
//                dt = 10 s (tests/physics/integrator_test.cpp, PhaseErrorOfCompositions).
//   blanes_moan4 Blanes & Moan (2002, J. Comput. Appl. Math. 142, Table 3, "SRKN_6^b"): a
//                Runge-Kutta-Nystrom composition optimised for forces that depend on position
//                (velocity-dependent drag enters through the time-symmetric kick). Seven kicks, all
//                weights below 0.40 in size, and an error constant about 10^4 times smaller: the same
//                orbit is 0.06 m off at dt = 30 s, so a 30 s step costs 7/9 of Yoshida's force
//                evaluations at 10 s and is two orders of magnitude more accurate.
//
// drift[s] precedes kick[s]; drift[kicks] closes the step. kick_time[s] is the kick's instant as a
// fraction of the step (the sum of the drifts before it), stated once so that it is exact.
#pragma once

#include <array>
#include <cmath>
#include <optional>
#include <string_view>

namespace kessler {

enum class Integrator { kYoshida4, kBlanesMoan4 };

struct Composition {
  static constexpr int kMaxKicks = 7;
  int kicks;
  std::array<double, kMaxKicks + 1> drift;
  std::array<double, kMaxKicks> kick;
  std::array<double, kMaxKicks> kick_time;
  // The largest |kick weight|: bounds the longest kick (for the drag rate limit).
  double largest_kick() const {
    double m = 0.0;
    for (int s = 0; s < kicks; ++s) m = std::fmax(m, std::fabs(kick[static_cast<std::size_t>(s)]));
    return m;
  }
};

namespace composition {

// Yoshida's weights: w1 = 1 / (2 - 2^(1/3)), w0 = -2^(1/3) / (2 - 2^(1/3)).
inline constexpr double kYoshidaW1 = 1.3512071919596576;
inline constexpr double kYoshidaW0 = -1.7024143839193153;
inline constexpr Composition kYoshida4{
    3,
    {kYoshidaW1 / 2.0, (kYoshidaW0 + kYoshidaW1) / 2.0, (kYoshidaW0 + kYoshidaW1) / 2.0, kYoshidaW1 / 2.0},
    {kYoshidaW1, kYoshidaW0, kYoshidaW1},
    {kYoshidaW1 / 2.0, 0.5, kYoshidaW1 / 2.0 + (kYoshidaW0 + kYoshidaW1)}};

// Blanes & Moan's SRKN_6^b: kick first and last (b1 .. b4 .. b1), drifts a1 a2 a3 a3 a2 a1.
inline constexpr double kBmA1 = 0.245298957184271, kBmA2 = 0.604872665711080, kBmA3 = 0.5 - (kBmA1 + kBmA2);
inline constexpr double kBmB1 = 0.0829844064174052, kBmB2 = 0.396309801498368, kBmB3 = -0.0390563049223486,
                        kBmB4 = 1.0 - 2.0 * (kBmB1 + kBmB2 + kBmB3);
inline constexpr Composition kBlanesMoan4{
    7,
    {0.0, kBmA1, kBmA2, kBmA3, kBmA3, kBmA2, kBmA1, 0.0},
    {kBmB1, kBmB2, kBmB3, kBmB4, kBmB3, kBmB2, kBmB1},
    {0.0, kBmA1, kBmA1 + kBmA2, 0.5, 1.0 - (kBmA1 + kBmA2), 1.0 - kBmA1, 1.0}};

}  // namespace composition

inline const Composition& composition_of(Integrator integrator) {
  return integrator == Integrator::kBlanesMoan4 ? composition::kBlanesMoan4 : composition::kYoshida4;
}

inline std::string_view integrator_name(Integrator integrator) {
  return integrator == Integrator::kBlanesMoan4 ? "blanes_moan4" : "yoshida4";
}

// The integrator of a name ("yoshida4", "blanes_moan4"), or nullopt.
inline std::optional<Integrator> integrator_from_name(std::string_view name) {
  for (Integrator i : {Integrator::kYoshida4, Integrator::kBlanesMoan4})
    if (name == integrator_name(i)) return i;
  return std::nullopt;
}

}  // namespace kessler
