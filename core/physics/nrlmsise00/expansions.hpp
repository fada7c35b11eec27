// The global expansions of NRLMSISE-00 (Picone et al. 2002, after Hedin's MSIS-86 eqs. A1-A22): a
// quantity's relative variation G(L) as a sum of terms in associated Legendre functions of latitude,
// harmonics of local solar time (diurnal, semidiurnal, terdiurnal), annual and semiannual day-of-year
// waves, the solar flux (F10.7 and its 81-day mean), geomagnetic activity (daily Ap, or the 3-hour Ap
// history), longitude and universal time.
//  - globe7: the full expansion, for the thermosphere's exospheric temperature, lower-boundary
//    temperature, gradient and densities.
//  - glob7s: the reduced expansion for the lower thermosphere and middle atmosphere temperature nodes
//    (it reuses the Legendre functions and time harmonics globe7 computed for the same input).
// The 23 switches (index 1..23, 0 selects units) each turn one kind of variation on (1), off (0), or
// keep only its main effect (2); switch 9 = -1 takes Ap from the 7-element history instead of the daily
// value. A switch of 0 removes the term exactly.
#pragma once

#include <array>

namespace kessler::nrlmsise00 {

// The model's inputs in its own units.
struct ModelInput {
  int day_of_year = 1;              // 1..366
  double ut_s = 0.0;                // universal time, seconds of the day
  double altitude_km = 0.0;         // geodetic altitude
  double latitude_deg = 0.0;        // geodetic latitude
  double longitude_deg = 0.0;       // east longitude
  double local_solar_time_h = 0.0;  // apparent local solar time
  double f107_avg = 150.0;          // 81-day centred mean of F10.7
  double f107 = 150.0;              // daily F10.7 of the previous day
  double ap = 4.0;                  // daily magnetic index
  // With switch 9 = -1: daily Ap, the 3-hour ap now and 3, 6, 9 h before, the means of the eight 3-hour
  // values 12-33 h and 36-57 h before.
  std::array<double, 7> ap_history{};
};

// The switches as the expansions read them: sw[i] is 1 only for a switch set to 1 (and sw[9] is the
// switch itself, -1/0/1); swc[i] is 1 for any positive switch (cross terms' "main effect").
struct Switches {
  std::array<double, 24> sw{};
  std::array<double, 24> swc{};
  // From the 24 settings (index 0: units, not used here).
  static Switches from(const std::array<int, 24>& settings);
  static Switches all_on();  // switches 1..23 = 1
};

// What globe7 leaves for glob7s and the caller: Legendre functions of latitude, local-time harmonics,
// the solar-flux and magnetic-activity terms of the input.
struct ExpansionState {
  double plg[4][9] = {};
  double ctloc = 0, stloc = 0, c2tloc = 0, s2tloc = 0, c3tloc = 0, s3tloc = 0;
  double dfa = 0;   // F10.7 81-day mean - 150
  double apdf = 0;  // daily Ap through the model's saturating function
  double apt = 0;   // 3-hour Ap history through its exponential weighting
};

// The relative variation G(L) with the parameter vector p (150 values); fills `state`.
double globe7(const double* p, const ModelInput& in, const Switches& s, ExpansionState& state);
// The reduced variation with p (100 values, p[99] == 2 marks the set); needs the state globe7 filled.
double glob7s(const double* p, const ModelInput& in, const Switches& s, const ExpansionState& state);

}  // namespace kessler::nrlmsise00
