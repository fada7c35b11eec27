// SGP4 initialisation: recover the Brouwer mean motion and semi-major axis from the Kozai elements,
// then the secular, drag and (for periods >= 225 min) deep-space coefficients.
#include <cmath>

#include "core/sgp4/sgp4.hpp"
#include "core/sgp4/sgp4_deep_space.hpp"
#include "core/sgp4/wgs72.hpp"

namespace kessler {

using namespace sgp4;

namespace {

// Greenwich mean sidereal time [rad] of a UT1 Julian date (IAU-82), as SGP4's "improved" mode uses it.
double gmst_iau82_rad(double jd_ut1) {
  const double tut1 = (jd_ut1 - 2451545.0) / 36525.0;
  double temp = -6.2e-6 * tut1 * tut1 * tut1 + 0.093104 * tut1 * tut1 +
                (876600.0 * 3600 + 8640184.812866) * tut1 + 67310.54841;  // seconds
  temp = std::fmod(temp * (kPi / 180.0) / 240.0, kTwoPi);
  if (temp < 0.0) temp += kTwoPi;
  return temp;
}

}  // namespace

double sgp4_epoch_days_since_1950(const UtcEpoch& epoch) {
  // The day fraction goes through hours, minutes and seconds and back, as the reference element
  // reader does; the verification output depends on these last bits for very eccentric orbits.
  double temp = epoch.jd_fraction() * 24.0;
  const double hour = std::floor(temp);
  temp = (temp - hour) * 60.0;
  const double minute = std::floor(temp);
  const double second = (temp - minute) * 60.0;
  const double jd = epoch.jd_whole() + ((second / 60.0 + minute) / 60.0 + hour) / 24.0;
  return jd - 2433281.5;
}

const char* sgp4_error_text(Sgp4Error error) {
  switch (error) {
    case Sgp4Error::kNone:
      return "no error";
    case Sgp4Error::kMeanEccentricity:
      return "mean eccentricity outside 0 <= e < 1";
    case Sgp4Error::kMeanMotion:
      return "mean motion not positive";
    case Sgp4Error::kPerturbedEccentricity:
      return "perturbed eccentricity outside 0 <= e <= 1";
    case Sgp4Error::kSemiLatusRectum:
      return "semi-latus rectum negative";
    case Sgp4Error::kDecayed:
      return "orbit radius below the Earth's surface (decayed)";
  }
  return "unknown SGP4 error";
}

Sgp4Record sgp4_initialise(const MeanElements& el) {
  Sgp4Record r;
  r.catalog_number = el.catalog_number;
  r.epoch_days_since_1950 = sgp4_epoch_days_since_1950(el.epoch);
  r.bstar = el.bstar_per_earth_radius;
  r.ecco = el.eccentricity;
  r.argpo = el.argument_of_perigee_rad;
  r.inclo = el.inclination_rad;
  r.mo = el.mean_anomaly_rad;
  r.nodeo = el.raan_rad;
  const double no_kozai = el.mean_motion_rad_min;

  constexpr double x2o3 = 2.0 / 3.0;
  constexpr double temp4 = 1.5e-12;
  const double ss = 78.0 / kEarthRadius_km + 1.0;
  const double qzms2ttemp = (120.0 - 78.0) / kEarthRadius_km;
  const double qzms2t = qzms2ttemp * qzms2ttemp * qzms2ttemp * qzms2ttemp;

  // Brouwer mean motion from the Kozai one (the theory's "initl").
  const double eccsq = r.ecco * r.ecco;
  const double omeosq = 1.0 - eccsq;
  const double rteosq = std::sqrt(omeosq);
  const double cosio = std::cos(r.inclo);
  const double cosio2 = cosio * cosio;
  const double ak = std::pow(kXke / no_kozai, x2o3);
  const double d1 = 0.75 * kJ2 * (3.0 * cosio2 - 1.0) / (rteosq * omeosq);
  double del = d1 / (ak * ak);
  const double adel = ak * (1.0 - del * del - del * (1.0 / 3.0 + 134.0 * del * del / 81.0));
  del = d1 / (adel * adel);
  r.no_unkozai = no_kozai / (1.0 + del);
  const double ao = std::pow(kXke / r.no_unkozai, x2o3);
  const double sinio = std::sin(r.inclo);
  const double po = ao * omeosq;
  const double con42 = 1.0 - 5.0 * cosio2;
  r.con41 = -con42 - cosio2 - cosio2;
  const double posq = po * po;
  const double rp = ao * (1.0 - r.ecco);
  r.gsto = gmst_iau82_rad(r.epoch_days_since_1950 + 2433281.5);

  if (omeosq >= 0.0 || r.no_unkozai >= 0.0) {
    r.simplified_drag = rp < 220.0 / kEarthRadius_km + 1.0;
    // Atmosphere parameter s and (q0 - s)^4, lowered for perigees below 156 km.
    double sfour = ss;
    double qzms24 = qzms2t;
    const double perige = (rp - 1.0) * kEarthRadius_km;
    if (perige < 156.0) {
      sfour = perige - 78.0;
      if (perige < 98.0) sfour = 20.0;
      const double qzms24temp = (120.0 - sfour) / kEarthRadius_km;
      qzms24 = qzms24temp * qzms24temp * qzms24temp * qzms24temp;
      sfour = sfour / kEarthRadius_km + 1.0;
    }
    const double pinvsq = 1.0 / posq;
    const double tsi = 1.0 / (ao - sfour);
    r.eta = ao * r.ecco * tsi;
    const double etasq = r.eta * r.eta;
    const double eeta = r.ecco * r.eta;
    const double psisq = std::fabs(1.0 - etasq);
    const double coef = qzms24 * std::pow(tsi, 4.0);
    const double coef1 = coef / std::pow(psisq, 3.5);
    const double cc2 = coef1 * r.no_unkozai *
                       (ao * (1.0 + 1.5 * etasq + eeta * (4.0 + etasq)) +
                        0.375 * kJ2 * tsi / psisq * r.con41 * (8.0 + 3.0 * etasq * (8.0 + etasq)));
    r.cc1 = r.bstar * cc2;
    double cc3 = 0.0;
    if (r.ecco > 1.0e-4) cc3 = -2.0 * coef * tsi * kJ3OverJ2 * r.no_unkozai * sinio / r.ecco;
    r.x1mth2 = 1.0 - cosio2;
    r.cc4 = 2.0 * r.no_unkozai * coef1 * ao * omeosq *
            (r.eta * (2.0 + 0.5 * etasq) + r.ecco * (0.5 + 2.0 * etasq) -
             kJ2 * tsi / (ao * psisq) *
                 (-3.0 * r.con41 * (1.0 - 2.0 * eeta + etasq * (1.5 - 0.5 * eeta)) +
                  0.75 * r.x1mth2 * (2.0 * etasq - eeta * (1.0 + etasq)) * std::cos(2.0 * r.argpo)));
    r.cc5 = 2.0 * coef1 * ao * omeosq * (1.0 + 2.75 * (etasq + eeta) + eeta * etasq);
    const double cosio4 = cosio2 * cosio2;
    const double temp1 = 1.5 * kJ2 * pinvsq * r.no_unkozai;
    const double temp2 = 0.5 * temp1 * kJ2 * pinvsq;
    const double temp3 = -0.46875 * kJ4 * pinvsq * pinvsq * r.no_unkozai;
    r.mdot = r.no_unkozai + 0.5 * temp1 * rteosq * r.con41 +
             0.0625 * temp2 * rteosq * (13.0 - 78.0 * cosio2 + 137.0 * cosio4);
    r.argpdot = -0.5 * temp1 * con42 + 0.0625 * temp2 * (7.0 - 114.0 * cosio2 + 395.0 * cosio4) +
                temp3 * (3.0 - 36.0 * cosio2 + 49.0 * cosio4);
    const double xhdot1 = -temp1 * cosio;
    r.nodedot = xhdot1 + (0.5 * temp2 * (4.0 - 19.0 * cosio2) + 2.0 * temp3 * (3.0 - 7.0 * cosio2)) * cosio;
    const double xpidot = r.argpdot + r.nodedot;
    r.omgcof = r.bstar * cc3 * std::cos(r.argpo);
    r.xmcof = 0.0;
    if (r.ecco > 1.0e-4) r.xmcof = -x2o3 * coef * r.bstar / eeta;
    r.nodecf = 3.5 * omeosq * xhdot1 * r.cc1;
    r.t2cof = 1.5 * r.cc1;
    // Guard against division by zero at an inclination of 180 degrees.
    if (std::fabs(cosio + 1.0) > 1.5e-12)
      r.xlcof = -0.25 * kJ3OverJ2 * sinio * (3.0 + 5.0 * cosio) / (1.0 + cosio);
    else
      r.xlcof = -0.25 * kJ3OverJ2 * sinio * (3.0 + 5.0 * cosio) / temp4;
    r.aycof = -0.5 * kJ3OverJ2 * sinio;
    const double delmotemp = 1.0 + r.eta * std::cos(r.mo);
    r.delmo = delmotemp * delmotemp * delmotemp;
    r.sinmao = std::sin(r.mo);
    r.x7thm1 = 7.0 * cosio2 - 1.0;

    if (2.0 * kPi / r.no_unkozai >= 225.0) {
      r.deep_space = true;
      r.simplified_drag = true;
      sgp4::DeepSpaceCommon common;
      sgp4::deep_space_common(r.epoch_days_since_1950, r.ecco, r.argpo, 0.0, r.inclo, r.nodeo, r.no_unkozai,
                              r, common);
      sgp4::deep_space_periodics(r, 0.0, true, r.ecco, r.inclo, r.nodeo, r.argpo, r.mo);
      sgp4::DeepSpaceMeanState state{common.em, 0.0, r.inclo, 0.0, common.nm, 0.0};
      sgp4::deep_space_initialise(common, 0.0, xpidot, eccsq, r, state);
    }

    if (!r.simplified_drag) {
      const double cc1sq = r.cc1 * r.cc1;
      r.d2 = 4.0 * ao * tsi * cc1sq;
      const double temp = r.d2 * tsi * r.cc1 / 3.0;
      r.d3 = (17.0 * ao + sfour) * temp;
      r.d4 = 0.5 * temp * ao * tsi * (221.0 * ao + 31.0 * sfour) * r.cc1;
      r.t3cof = r.d2 + 2.0 * cc1sq;
      r.t4cof = 0.25 * (3.0 * r.d3 + r.cc1 * (12.0 * r.d2 + 10.0 * cc1sq));
      r.t5cof =
          0.2 * (3.0 * r.d4 + 12.0 * r.cc1 * r.d3 + 6.0 * r.d2 * r.d2 + 15.0 * cc1sq * (2.0 * r.d2 + cc1sq));
    }
  }

  const Sgp4State at_epoch = sgp4_propagate(r, 0.0);
  r.init_error = at_epoch.error;
  return r;
}

}  // namespace kessler
