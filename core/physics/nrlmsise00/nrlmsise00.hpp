// NRLMSISE-00: the empirical model of the atmosphere's temperature and composition from the ground to
// the exobase (Picone, Hedin, Drob, "NRLMSISE-00 empirical model of the atmosphere: statistical
// comparisons and scientific issues", J. Geophys. Res. 107(A12), 1468, 2002). Its parts here:
//  - coefficients.{hpp,cpp}: the parameter arrays (generated from tests/data/nrlmsise00/coefficients.json);
//  - expansions.{hpp,cpp}: the global expansions globe7/glob7s and the 23 switches;
//  - profiles.{hpp,cpp}: temperature profiles, density integrals, splines, turbopause and corrections;
//  - nrlmsise00.{hpp,cpp}: the thermosphere (above 72.5 km: each species' diffusive and mixed density
//    from its value at 120 km) and the whole model (below 72.5 km N2 through the middle/lower atmosphere
//    profile, the other species by their mixing ratios).
// Validated against the model's 17 standard test cases (tests/physics/nrlmsise00_test.cpp).
#pragma once

#include "core/physics/nrlmsise00/expansions.hpp"
#include "core/physics/nrlmsise00/profiles.hpp"

namespace kessler {

// Inputs: day of year, UT seconds, altitude [km], geodetic latitude and longitude [deg], local solar
// time [h], F10.7 81-day mean and previous day's value, daily Ap (and the Ap history for switch 9 = -1).
using MsisInput = nrlmsise00::ModelInput;

struct MsisOutput {
  // Number densities [1/m^3].
  double he = 0, o = 0, n2 = 0, o2 = 0, ar = 0, h = 0, n = 0, anomalous_o = 0;
  // Total mass density [kg/m^3] of He, O, N2, O2, Ar, H and N (the model's "total mass density").
  double rho_kg_m3 = 0;
  // The same with anomalous oxygen (hot O and O+ above ~500 km): the effective density for drag that
  // the model's authors recommend for satellite drag (their gtd7d); differs from rho above ~500 km.
  double rho_drag_kg_m3 = 0;
  double exospheric_temperature_k = 0;
  double temperature_k = 0;  // at the altitude
};

// The model at one point with the given switches (default: all on, daily Ap).
MsisOutput nrlmsise00_density(const MsisInput& input,
                              const nrlmsise00::Switches& switches = nrlmsise00::Switches::all_on());

namespace nrlmsise00 {

// Species' mixed densities at their turbopause heights for one regime of a column (computed on first use).
struct TurbopauseCache {
  bool has[9] = {};
  double b[9] = {};
};

// The thermosphere along one vertical column (fixed time, latitude, longitude, local time, solar
// inputs): the global expansions once, then the profile at any altitude above 72.5 km. at(h) gives the
// same bits as nrlmsise00_density with the input's altitude set to h (the model's expansions do not
// depend on altitude, only which of them it uses: above/below 120 km, 72.5 km and 300 km).
struct ColumnTerms {
  ColumnTerms(const ModelInput& input, const Switches& switches);
  MsisOutput at(double altitude_km) const;

  ModelInput input;
  Switches switches;
  Profiles profiles;
  ExpansionState ex;
  double tinf_varying = 0, tinf_mean = 0;  // exospheric temperature above / below 120 km
  double g0_varying = 0, g0_mean = 0;      // temperature gradient at 120 km above / below 72.5 km
  double tlb = 0;                          // temperature at 120 km
  TemperatureNodes nodes_low, nodes_high;  // lower-thermosphere nodes below / above 300 km
  double g[9] = {};                        // each species' variation at 120 km (model order)
  // Filled by at(): not thread-safe, one column per thread.
  mutable TurbopauseCache turbopause[8];
};

}  // namespace nrlmsise00
}  // namespace kessler
