// SGP4/SDP4 analytic propagation of mean elements (Hoots & Roehrich, Spacetrack Report #3, with the
// corrections of Vallado, Crawford, Hujsak & Kelso, "Revisiting Spacetrack Report #3", AIAA 2006-6753;
// "improved" operation mode, WGS-72 constants). Output frame: TEME of date, km and km/s.
//
// Initialisation turns one element set into a record of coefficients; propagation is a pure function of
// that record and the time since epoch, so any number of threads may share one record.
#pragma once

#include <array>
#include <string>

#include "core/sgp4/mean_elements.hpp"

namespace kessler {

// The error codes of the reference implementation, so that verification can compare them.
enum class Sgp4Error : int {
  kNone = 0,
  kMeanEccentricity = 1,       // mean eccentricity outside [0, 1) (-0.001 tolerated)
  kMeanMotion = 2,             // mean motion <= 0
  kPerturbedEccentricity = 3,  // eccentricity after lunisolar periodics outside [0, 1]
  kSemiLatusRectum = 4,        // semi-latus rectum < 0
  kDecayed = 6,                // radius below one Earth radius: the object has decayed
};

const char* sgp4_error_text(Sgp4Error error);

// Coefficients of one initialised element set. Names follow the theory's symbols (Vallado et al. 2006).
struct Sgp4Record {
  std::uint64_t catalog_number = 0;
  double epoch_days_since_1950 = 0.0;  // days since 1949-12-31T00:00 UTC
  bool deep_space = false;             // orbital period >= 225 min: SDP4 terms
  bool simplified_drag = false;        // perigee < 220 km (or deep space): drop higher drag terms
  Sgp4Error init_error = Sgp4Error::kNone;

  // Elements (after deep-space periodics at epoch where deep_space).
  double bstar = 0, ecco = 0, inclo = 0, nodeo = 0, argpo = 0, mo = 0, no_unkozai = 0;
  // Near-Earth secular and drag coefficients.
  double aycof = 0, con41 = 0, cc1 = 0, cc4 = 0, cc5 = 0, d2 = 0, d3 = 0, d4 = 0, delmo = 0, eta = 0;
  double argpdot = 0, omgcof = 0, sinmao = 0, t2cof = 0, t3cof = 0, t4cof = 0, t5cof = 0;
  double x1mth2 = 0, x7thm1 = 0, mdot = 0, nodedot = 0, xlcof = 0, xmcof = 0, nodecf = 0;
  double gsto = 0;  // Greenwich sidereal angle at epoch [rad]
  // Deep-space: resonance and lunisolar coefficients.
  int irez = 0;  // 0 none, 1 one-day (synchronous), 2 half-day resonance
  double d2201 = 0, d2211 = 0, d3210 = 0, d3222 = 0, d4410 = 0, d4422 = 0, d5220 = 0, d5232 = 0;
  double d5421 = 0, d5433 = 0, dedt = 0, del1 = 0, del2 = 0, del3 = 0, didt = 0, dmdt = 0;
  double dnodt = 0, domdt = 0, e3 = 0, ee2 = 0, peo = 0, pgho = 0, pho = 0, pinco = 0, plo = 0;
  double se2 = 0, se3 = 0, sgh2 = 0, sgh3 = 0, sgh4 = 0, sh2 = 0, sh3 = 0, si2 = 0, si3 = 0;
  double sl2 = 0, sl3 = 0, sl4 = 0, xfact = 0, xgh2 = 0, xgh3 = 0, xgh4 = 0, xh2 = 0, xh3 = 0;
  double xi2 = 0, xi3 = 0, xl2 = 0, xl3 = 0, xl4 = 0, xlamo = 0, zmol = 0, zmos = 0;
};

struct Sgp4State {
  std::array<double, 3> position_km{};
  std::array<double, 3> velocity_km_s{};
  Sgp4Error error = Sgp4Error::kNone;
};

// Days since 1949-12-31T00:00 UTC, the time argument of SGP4's deep-space and sidereal terms.
double sgp4_epoch_days_since_1950(const UtcEpoch& epoch);

// Initialises a record from mean elements. record.init_error is set when the elements cannot be
// propagated even at epoch.
Sgp4Record sgp4_initialise(const MeanElements& elements);

// TEME state `minutes_since_epoch` after the element set's epoch. On kDecayed the position is still
// filled (as in the reference implementation); on other errors it is left zero.
Sgp4State sgp4_propagate(const Sgp4Record& record, double minutes_since_epoch);

}  // namespace kessler
