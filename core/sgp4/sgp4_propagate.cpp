// SGP4 propagation: secular gravity and drag, deep-space terms where needed, long-period periodics,
// Kepler's equation, short-period periodics, and the TEME position and velocity.
#include <cmath>

#include "core/sgp4/sgp4.hpp"
#include "core/sgp4/sgp4_deep_space.hpp"
#include "core/sgp4/wgs72.hpp"

namespace kessler {

using namespace sgp4;

Sgp4State sgp4_propagate(const Sgp4Record& r, double t) {
  constexpr double temp4 = 1.5e-12;
  constexpr double x2o3 = 2.0 / 3.0;
  const double vkmpersec = kEarthRadius_km * kXke / 60.0;
  Sgp4State out;

  // Secular gravity and atmospheric drag.
  const double xmdf = r.mo + r.mdot * t;
  const double argpdf = r.argpo + r.argpdot * t;
  const double nodedf = r.nodeo + r.nodedot * t;
  double argpm = argpdf;
  double mm = xmdf;
  const double t2 = t * t;
  double nodem = nodedf + r.nodecf * t2;
  double tempa = 1.0 - r.cc1 * t;
  double tempe = r.bstar * r.cc4 * t;
  double templ = r.t2cof * t2;
  if (!r.simplified_drag) {
    const double delomg = r.omgcof * t;
    const double delmtemp = 1.0 + r.eta * std::cos(xmdf);
    const double delm = r.xmcof * (delmtemp * delmtemp * delmtemp - r.delmo);
    const double temp = delomg + delm;
    mm = xmdf + temp;
    argpm = argpdf - temp;
    const double t3 = t2 * t;
    const double t4 = t3 * t;
    tempa = tempa - r.d2 * t2 - r.d3 * t3 - r.d4 * t4;
    tempe = tempe + r.bstar * r.cc5 * (std::sin(mm) - r.sinmao);
    templ = templ + r.t3cof * t3 + t4 * (r.t4cof + t * r.t5cof);
  }

  double nm = r.no_unkozai;
  double em = r.ecco;
  double inclm = r.inclo;
  if (r.deep_space) {
    DeepSpaceMeanState s{em, argpm, inclm, mm, nm, nodem};
    deep_space_secular(r, t, s);
    em = s.em;
    argpm = s.argpm;
    inclm = s.inclm;
    mm = s.mm;
    nm = s.nm;
    nodem = s.nodem;
  }
  if (nm <= 0.0) {
    out.error = Sgp4Error::kMeanMotion;
    return out;
  }
  const double am = std::pow(kXke / nm, x2o3) * tempa * tempa;
  nm = kXke / std::pow(am, 1.5);
  em = em - tempe;
  if (em >= 1.0 || em < -0.001) {
    out.error = Sgp4Error::kMeanEccentricity;
    return out;
  }
  if (em < 1.0e-6) em = 1.0e-6;
  mm = mm + r.no_unkozai * templ;
  double xlm = mm + argpm + nodem;
  nodem = std::fmod(nodem, kTwoPi);
  argpm = std::fmod(argpm, kTwoPi);
  xlm = std::fmod(xlm, kTwoPi);
  mm = std::fmod(xlm - argpm - nodem, kTwoPi);

  // Lunar-solar periodics.
  double sinim = std::sin(inclm);
  double cosim = std::cos(inclm);
  double ep = em;
  double xincp = inclm;
  double argpp = argpm;
  double nodep = nodem;
  double mp = mm;
  double sinip = sinim;
  double cosip = cosim;
  double aycof = r.aycof, xlcof = r.xlcof, con41 = r.con41, x1mth2 = r.x1mth2, x7thm1 = r.x7thm1;
  if (r.deep_space) {
    deep_space_periodics(r, t, false, ep, xincp, nodep, argpp, mp);
    if (xincp < 0.0) {
      xincp = -xincp;
      nodep = nodep + kPi;
      argpp = argpp - kPi;
    }
    if (ep < 0.0 || ep > 1.0) {
      out.error = Sgp4Error::kPerturbedEccentricity;
      return out;
    }
    sinip = std::sin(xincp);
    cosip = std::cos(xincp);
    aycof = -0.5 * kJ3OverJ2 * sinip;
    if (std::fabs(cosip + 1.0) > 1.5e-12)
      xlcof = -0.25 * kJ3OverJ2 * sinip * (3.0 + 5.0 * cosip) / (1.0 + cosip);
    else
      xlcof = -0.25 * kJ3OverJ2 * sinip * (3.0 + 5.0 * cosip) / temp4;
  }

  // Long-period periodics.
  const double axnl = ep * std::cos(argpp);
  double temp = 1.0 / (am * (1.0 - ep * ep));
  const double aynl = ep * std::sin(argpp) + temp * aycof;
  const double xl = mp + argpp + nodep + temp * xlcof * axnl;

  // Kepler's equation in the equinoctial form (Newton-Raphson, steps limited to 0.95 rad).
  const double u = std::fmod(xl - nodep, kTwoPi);
  double eo1 = u;
  double tem5 = 9999.9;
  double sineo1 = 0.0, coseo1 = 0.0;
  for (int ktr = 1; std::fabs(tem5) >= 1.0e-12 && ktr <= 10; ++ktr) {
    sineo1 = std::sin(eo1);
    coseo1 = std::cos(eo1);
    tem5 = 1.0 - coseo1 * axnl - sineo1 * aynl;
    tem5 = (u - aynl * coseo1 + axnl * sineo1 - eo1) / tem5;
    if (std::fabs(tem5) >= 0.95) tem5 = tem5 > 0.0 ? 0.95 : -0.95;
    eo1 = eo1 + tem5;
  }

  // Short-period periodics.
  const double ecose = axnl * coseo1 + aynl * sineo1;
  const double esine = axnl * sineo1 - aynl * coseo1;
  const double el2 = axnl * axnl + aynl * aynl;
  const double pl = am * (1.0 - el2);
  if (pl < 0.0) {
    out.error = Sgp4Error::kSemiLatusRectum;
    return out;
  }
  const double rl = am * (1.0 - ecose);
  const double rdotl = std::sqrt(am) * esine / rl;
  const double rvdotl = std::sqrt(pl) / rl;
  const double betal = std::sqrt(1.0 - el2);
  temp = esine / (1.0 + betal);
  const double sinu = am / rl * (sineo1 - aynl - axnl * temp);
  const double cosu = am / rl * (coseo1 - axnl + aynl * temp);
  double su = std::atan2(sinu, cosu);
  const double sin2u = (cosu + cosu) * sinu;
  const double cos2u = 1.0 - 2.0 * sinu * sinu;
  temp = 1.0 / pl;
  const double temp1 = 0.5 * kJ2 * temp;
  const double temp2 = temp1 * temp;
  if (r.deep_space) {
    const double cosisq = cosip * cosip;
    con41 = 3.0 * cosisq - 1.0;
    x1mth2 = 1.0 - cosisq;
    x7thm1 = 7.0 * cosisq - 1.0;
  }
  const double mrt = rl * (1.0 - 1.5 * temp2 * betal * con41) + 0.5 * temp1 * x1mth2 * cos2u;
  su = su - 0.25 * temp2 * x7thm1 * sin2u;
  const double xnode = nodep + 1.5 * temp2 * cosip * sin2u;
  const double xinc = xincp + 1.5 * temp2 * cosip * sinip * cos2u;
  const double mvt = rdotl - nm * temp1 * x1mth2 * sin2u / kXke;
  const double rvdot = rvdotl + nm * temp1 * (x1mth2 * cos2u + 1.5 * con41) / kXke;

  // Orientation vectors and the TEME state.
  const double sinsu = std::sin(su);
  const double cossu = std::cos(su);
  const double snod = std::sin(xnode);
  const double cnod = std::cos(xnode);
  const double sini = std::sin(xinc);
  const double cosi = std::cos(xinc);
  const double xmx = -snod * cosi;
  const double xmy = cnod * cosi;
  const double ux = xmx * sinsu + cnod * cossu;
  const double uy = xmy * sinsu + snod * cossu;
  const double uz = sini * sinsu;
  const double vx = xmx * cossu - cnod * sinsu;
  const double vy = xmy * cossu - snod * sinsu;
  const double vz = sini * cossu;
  const double mr = mrt * kEarthRadius_km;
  out.position_km = {mr * ux, mr * uy, mr * uz};
  out.velocity_km_s = {(mvt * ux + rvdot * vx) * vkmpersec, (mvt * uy + rvdot * vy) * vkmpersec,
                       (mvt * uz + rvdot * vz) * vkmpersec};
  if (mrt < 1.0) out.error = Sgp4Error::kDecayed;
  return out;
}

}  // namespace kessler
