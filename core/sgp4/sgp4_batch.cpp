#include "core/sgp4/sgp4_batch.hpp"

#include <algorithm>
#include <cmath>

#include "core/sgp4/simd_math.hpp"
#include "core/sgp4/wgs72.hpp"

namespace kessler {

using namespace sgp4;

namespace {

// A sound near-Earth record whose coefficients fill the slots of deep-space objects and the padding,
// so that vector lanes never compute with zeros (400 km circular orbit, 51.6 deg).
const Sgp4Record& dummy_near_earth_record() {
  static const Sgp4Record record = [] {
    MeanElements el;
    el.mean_motion_rad_min = 15.5 * 2.0 * kPi / 1440.0;
    el.eccentricity = 0.001;
    el.inclination_rad = 51.6 * kPi / 180.0;
    el.bstar_per_earth_radius = 1e-4;
    return sgp4_initialise(el);
  }();
  return record;
}

}  // namespace

void Sgp4Batch::assign(const std::vector<Sgp4Record>& records) {
  records_ = records;
  const std::size_t n = records.size();
  const std::size_t padded = n + kLanes;
  near_.assign(n, 0);
  near_count_ = 0;
  for (auto* v : {&mo_,   &mdot_,  &argpo_,  &argpdot_, &nodeo_,  &nodedot_, &nodecf_, &cc1_,
                  &bcc4_, &t2cof_, &omgcof_, &eta_,     &xmcof_,  &delmo_,   &d2_,     &d3_,
                  &d4_,   &bcc5_,  &sinmao_, &t3cof_,   &t4cof_,  &t5cof_,   &ecco_,   &no_,
                  &a0_,   &aycof_, &xlcof_,  &con41_,   &x1mth2_, &x7thm1_,  &cosio_,  &sinio_})
    v->assign(padded, 0.0);
  for (std::size_t i = 0; i < padded; ++i) {
    const bool near = i < n && !records[i].deep_space && records[i].init_error == Sgp4Error::kNone;
    const Sgp4Record& r = near ? records[i] : dummy_near_earth_record();
    if (near) {
      near_[i] = 1;
      ++near_count_;
    }
    mo_[i] = r.mo;
    mdot_[i] = r.mdot;
    argpo_[i] = r.argpo;
    argpdot_[i] = r.argpdot;
    nodeo_[i] = r.nodeo;
    nodedot_[i] = r.nodedot;
    nodecf_[i] = r.nodecf;
    cc1_[i] = r.cc1;
    bcc4_[i] = r.bstar * r.cc4;
    t2cof_[i] = r.t2cof;
    // With simplified drag the extra terms vanish: zero coefficients give the same numbers exactly.
    const bool full = !r.simplified_drag;
    omgcof_[i] = full ? r.omgcof : 0.0;
    eta_[i] = r.eta;
    xmcof_[i] = full ? r.xmcof : 0.0;
    delmo_[i] = r.delmo;
    d2_[i] = full ? r.d2 : 0.0;
    d3_[i] = full ? r.d3 : 0.0;
    d4_[i] = full ? r.d4 : 0.0;
    bcc5_[i] = full ? r.bstar * r.cc5 : 0.0;
    sinmao_[i] = r.sinmao;
    t3cof_[i] = full ? r.t3cof : 0.0;
    t4cof_[i] = full ? r.t4cof : 0.0;
    t5cof_[i] = full ? r.t5cof : 0.0;
    ecco_[i] = r.ecco;
    no_[i] = r.no_unkozai;
    a0_[i] = std::pow(kXke / r.no_unkozai, 2.0 / 3.0);
    aycof_[i] = r.aycof;
    xlcof_[i] = r.xlcof;
    con41_[i] = r.con41;
    x1mth2_[i] = r.x1mth2;
    x7thm1_[i] = r.x7thm1;
    cosio_[i] = std::cos(r.inclo);
    sinio_[i] = std::sin(r.inclo);
  }
}

void Sgp4Batch::propagate_block(std::size_t first, std::size_t count, const double* minutes,
                                const Sgp4BatchOutput& out) const {
  constexpr std::size_t L = kLanes;
  // Lanes beyond `count` repeat the block's first object, so every lane computes sound numbers.
  alignas(64) double t[L], u[L], axnl[L], aynl[L], am[L], nm[L], nodep[L], eo1[L], sineo1[L], coseo1[L];
  alignas(64) int err_ecc[L], err_pl[L], err_decay[L];
  // Coefficient arrays are padded, so lanes past `count` read harmless dummy coefficients; their
  // times repeat the block's first object.
  for (std::size_t l = 0; l < L; ++l) t[l] = minutes[first + (l < count ? l : 0)];

    // Secular gravity and drag, long-period periodics.
#pragma omp simd
  for (std::size_t l = 0; l < L; ++l) {
    const std::size_t i = first + l;
    const double tl = t[l];
    const double xmdf = mo_[i] + mdot_[i] * tl;
    const double argpdf = argpo_[i] + argpdot_[i] * tl;
    const double nodedf = nodeo_[i] + nodedot_[i] * tl;
    const double t2 = tl * tl;
    double nodem = nodedf + nodecf_[i] * t2;
    double s_xmdf, c_xmdf;
    simd_sincos(xmdf, s_xmdf, c_xmdf);
    const double delomg = omgcof_[i] * tl;
    const double delmtemp = 1.0 + eta_[i] * c_xmdf;
    const double delm = xmcof_[i] * (delmtemp * delmtemp * delmtemp - delmo_[i]);
    const double temp = delomg + delm;
    double mm = xmdf + temp;
    double argpm = argpdf - temp;
    const double t3 = t2 * tl;
    const double t4 = t3 * tl;
    const double tempa = 1.0 - cc1_[i] * tl - d2_[i] * t2 - d3_[i] * t3 - d4_[i] * t4;
    double s_mm, c_mm;
    simd_sincos(mm, s_mm, c_mm);
    const double tempe = bcc4_[i] * tl + bcc5_[i] * (s_mm - sinmao_[i]);
    const double templ = t2cof_[i] * t2 + t3cof_[i] * t3 + t4 * (t4cof_[i] + tl * t5cof_[i]);

    const double a = a0_[i] * tempa * tempa;
    nm[l] = kXke / (a * std::sqrt(a));
    am[l] = a;
    double em = ecco_[i] - tempe;
    err_ecc[l] = (em >= 1.0) | (em < -0.001);
    em = em < 1.0e-6 ? 1.0e-6 : em;
    mm = mm + no_[i] * templ;
    double xlm = mm + argpm + nodem;
    nodem = simd_fmod_two_pi(nodem);
    argpm = simd_fmod_two_pi(argpm);
    xlm = simd_fmod_two_pi(xlm);
    mm = simd_fmod_two_pi(xlm - argpm - nodem);

    double s_argp, c_argp;
    simd_sincos(argpm, s_argp, c_argp);
    axnl[l] = em * c_argp;
    const double tmp = 1.0 / (a * (1.0 - em * em));
    aynl[l] = em * s_argp + tmp * aycof_[i];
    const double xl = mm + argpm + nodem + tmp * xlcof_[i] * axnl[l];
    u[l] = simd_fmod_two_pi(xl - nodem);
    nodep[l] = nodem;
    eo1[l] = u[l];
  }

  // Kepler's equation: Newton-Raphson per lane until every lane has converged (at most 10 steps).
  alignas(64) int active[L];
  for (std::size_t l = 0; l < L; ++l) active[l] = 1;
  for (int iteration = 0; iteration < 10; ++iteration) {
    int any = 0;
#pragma omp simd reduction(| : any)
    for (std::size_t l = 0; l < L; ++l) {
      double s, c;
      simd_sincos(eo1[l], s, c);
      double tem5 = 1.0 - c * axnl[l] - s * aynl[l];
      tem5 = (u[l] - aynl[l] * c + axnl[l] * s - eo1[l]) / tem5;
      tem5 = tem5 >= 0.95 ? 0.95 : (tem5 <= -0.95 ? -0.95 : tem5);
      const int on = active[l];
      sineo1[l] = on ? s : sineo1[l];
      coseo1[l] = on ? c : coseo1[l];
      eo1[l] = on ? eo1[l] + tem5 : eo1[l];
      active[l] = on && std::fabs(tem5) >= 1.0e-12;
      any |= active[l];
    }
    if (!any) break;
  }

  // Short-period periodics and the TEME state.
  const double vkmpersec = kEarthRadius_km * kXke / 60.0;
  const double ps = out.position_scale, vs = out.velocity_scale;
#pragma omp simd
  for (std::size_t l = 0; l < L; ++l) {
    const std::size_t i = first + l;
    const double a = am[l];
    const double ecose = axnl[l] * coseo1[l] + aynl[l] * sineo1[l];
    const double esine = axnl[l] * sineo1[l] - aynl[l] * coseo1[l];
    const double el2 = axnl[l] * axnl[l] + aynl[l] * aynl[l];
    const double pl = a * (1.0 - el2);
    err_pl[l] = pl < 0.0;
    const double pl_safe = pl < 0.0 ? 1.0 : pl;
    const double rl = a * (1.0 - ecose);
    const double rdotl = std::sqrt(a) * esine / rl;
    const double rvdotl = std::sqrt(pl_safe) / rl;
    const double betal = std::sqrt(1.0 - (el2 < 1.0 ? el2 : 0.0));
    const double temp = esine / (1.0 + betal);
    const double sinu = a / rl * (sineo1[l] - aynl[l] - axnl[l] * temp);
    const double cosu = a / rl * (coseo1[l] - axnl[l] + aynl[l] * temp);
    const double sin2u = (cosu + cosu) * sinu;
    const double cos2u = 1.0 - 2.0 * sinu * sinu;
    const double tinv = 1.0 / pl_safe;
    const double temp1 = 0.5 * kJ2 * tinv;
    const double temp2 = temp1 * tinv;
    const double cosip = cosio_[i], sinip = sinio_[i];
    const double mrt = rl * (1.0 - 1.5 * temp2 * betal * con41_[i]) + 0.5 * temp1 * x1mth2_[i] * cos2u;
    // su = atan2(sinu, cosu) - d; its sine and cosine by rotating the unit vector (sinu, cosu) by -d.
    const double d = 0.25 * temp2 * x7thm1_[i] * sin2u;
    const double norm = 1.0 / std::sqrt(sinu * sinu + cosu * cosu);
    double s_d, c_d;
    simd_sincos(d, s_d, c_d);
    const double sinsu = sinu * norm * c_d - cosu * norm * s_d;
    const double cossu = cosu * norm * c_d + sinu * norm * s_d;
    const double xnode = nodep[l] + 1.5 * temp2 * cosip * sin2u;
    const double dinc = 1.5 * temp2 * cosip * sinip * cos2u;
    // sin/cos of (inclo + dinc) by the addition theorem.
    double s_di, c_di;
    simd_sincos(dinc, s_di, c_di);
    const double sini = sinip * c_di + cosip * s_di;
    const double cosi = cosip * c_di - sinip * s_di;
    const double mvt = rdotl - nm[l] * temp1 * x1mth2_[i] * sin2u / kXke;
    const double rvdot = rvdotl + nm[l] * temp1 * (x1mth2_[i] * cos2u + 1.5 * con41_[i]) / kXke;
    double snod, cnod;
    simd_sincos(xnode, snod, cnod);
    const double xmx = -snod * cosi;
    const double xmy = cnod * cosi;
    const double ux = xmx * sinsu + cnod * cossu;
    const double uy = xmy * sinsu + snod * cossu;
    const double uz = sini * sinsu;
    const double vx = xmx * cossu - cnod * sinsu;
    const double vy = xmy * cossu - snod * sinsu;
    const double vz = sini * cossu;
    const double mr = mrt * kEarthRadius_km * ps;
    const double vk = vkmpersec * vs;
    err_decay[l] = mrt < 1.0;
    t[l] = mr * ux;
    u[l] = mr * uy;
    axnl[l] = mr * uz;
    aynl[l] = (mvt * ux + rvdot * vx) * vk;
    am[l] = (mvt * uy + rvdot * vy) * vk;
    nm[l] = (mvt * uz + rvdot * vz) * vk;
  }
  for (std::size_t l = 0; l < count; ++l) {
    const std::size_t i = first + l;
    const Sgp4Error e = err_ecc[l]     ? Sgp4Error::kMeanEccentricity
                        : err_pl[l]    ? Sgp4Error::kSemiLatusRectum
                        : err_decay[l] ? Sgp4Error::kDecayed
                                       : Sgp4Error::kNone;
    if (out.error) out.error[i] = e;
    if (e != Sgp4Error::kNone && e != Sgp4Error::kDecayed) {
      out.x[i] = out.y[i] = out.z[i] = out.vx[i] = out.vy[i] = out.vz[i] = 0.0;
      continue;
    }
    out.x[i] = t[l];
    out.y[i] = u[l];
    out.z[i] = axnl[l];
    out.vx[i] = aynl[l];
    out.vy[i] = am[l];
    out.vz[i] = nm[l];
  }
}

void Sgp4Batch::propagate(const double* minutes, const Sgp4BatchOutput& out, std::size_t begin,
                          std::size_t end) const {
  // Runs of near-Earth objects go through the vector path in blocks; other objects one by one.
  std::size_t i = begin;
  while (i < end) {
    if (!near_[i]) {
      const Sgp4State s = records_[i].init_error != Sgp4Error::kNone
                              ? Sgp4State{{}, {}, records_[i].init_error}
                              : sgp4_propagate(records_[i], minutes[i]);
      out.x[i] = s.position_km[0] * out.position_scale;
      out.y[i] = s.position_km[1] * out.position_scale;
      out.z[i] = s.position_km[2] * out.position_scale;
      out.vx[i] = s.velocity_km_s[0] * out.velocity_scale;
      out.vy[i] = s.velocity_km_s[1] * out.velocity_scale;
      out.vz[i] = s.velocity_km_s[2] * out.velocity_scale;
      if (out.error) out.error[i] = s.error;
      ++i;
      continue;
    }
    std::size_t run = 1;
    while (run < kLanes && i + run < end && near_[i + run]) ++run;
    propagate_block(i, run, minutes, out);
    i += run;
  }
}

void Sgp4Batch::propagate_all(const double* minutes, const Sgp4BatchOutput& out) const {
  const std::size_t n = size();
  const std::size_t chunk = 64 * kLanes;
  const std::size_t chunks = (n + chunk - 1) / chunk;
#pragma omp parallel for schedule(dynamic, 4)
  for (std::size_t c = 0; c < chunks; ++c) propagate(minutes, out, c * chunk, std::min(n, (c + 1) * chunk));
}

}  // namespace kessler
