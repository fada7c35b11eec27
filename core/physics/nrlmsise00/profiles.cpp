#include "core/physics/nrlmsise00/profiles.hpp"

#include <cmath>

namespace kessler::nrlmsise00 {
namespace {

constexpr double kGasConstant = 831.4;  // R in the model's units (cgs / km)

// One spline region: nodes z[0..n) (descending altitudes) with temperatures tn and end gradients tgn;
// on return xs, ys, y2 hold the normalised abscissae, 1/T and the second derivatives, and the result is
// zeta(z[n-1], z[0]).
double region_spline(const Profiles& pr, const double* z, const double* tn, const double* tgn, int n,
                     double* xs, double* ys, double* y2) {
  const double z1 = z[0], z2 = z[n - 1], t1 = tn[0], t2 = tn[n - 1];
  const double zgdif = pr.zeta(z2, z1);
  for (int k = 0; k < n; ++k) {
    xs[k] = pr.zeta(z[k], z1) / zgdif;
    ys[k] = 1.0 / tn[k];
  }
  const double yd1 = -tgn[0] / (t1 * t1) * zgdif;
  const double yd2 = -tgn[1] / (t2 * t2) * zgdif * std::pow((pr.re() + z2) / (pr.re() + z1), 2.0);
  spline_second_derivatives(xs, ys, n, yd1, yd2, y2);
  return zgdif;
}

// Temperature at z in a region and, for xm != 0, the region's factor on a density carried from its top
// node: (T1 / T) exp(-gamma integral(1/T)). `power` is 1 + alpha (densu) or 1 (densm).
double region_profile(const Profiles& pr, double z, double xm, double power, const double* zn,
                      const double* tn, const double* tgn, int n, double& tz) {
  double xs[10], ys[10], y2[10];
  const double zgdif = region_spline(pr, zn, tn, tgn, n, xs, ys, y2);
  const double x = pr.zeta(z, zn[0]) / zgdif;
  tz = 1.0 / spline_value(xs, ys, y2, n, x);
  if (xm == 0.0) return 1.0;
  const double glb = pr.gsurf() / std::pow(1.0 + zn[0] / pr.re(), 2.0);
  const double gamm = xm * glb * zgdif / kGasConstant;
  double expl = gamm * spline_integral(xs, ys, y2, n, x);
  if (expl > 50.0 || tz <= 0.0) expl = 50.0;
  return std::pow(tn[0] / tz, power) * std::exp(-expl);
}

}  // namespace

Profiles Profiles::at_latitude(double latitude_deg) {
  constexpr double kDegToRad = 1.74533e-2;
  const double c2 = std::cos(2.0 * kDegToRad * latitude_deg);
  Profiles p;
  p.gsurf_ = 980.616 * (1.0 - 0.0026373 * c2);
  p.re_ = 2.0 * p.gsurf_ / (3.085462e-6 + 2.27e-9 * c2) * 1.0e-5;
  return p;
}

double Profiles::scale_height(double alt, double xm, double temp) const {
  const double g = gsurf_ / std::pow(1.0 + alt / re_, 2.0);
  return kGasConstant * temp / (g * xm);
}

double Profiles::densu(double alt, double dlb, double tinf, double tlb, double xm, double alpha, double& tz,
                       double zlb, double s2, const double zn1[5], double tn1[5], double tgn1[2]) const {
  const double za = zn1[0];
  const double z = alt > za ? alt : za;
  // Bates temperature above za (and at za, the lower region's top node).
  const double zg2 = zeta(z, zlb);
  const double tt = tinf - (tinf - tlb) * std::exp(-s2 * zg2);
  tz = tt;
  double result = tz;
  if (alt < za) {
    tgn1[0] = (tinf - tt) * s2 * std::pow((re_ + zlb) / (re_ + za), 2.0);
    tn1[0] = tt;
    // Temperature (and density factor) along the lower thermosphere's spline.
    const double zb = alt > zn1[4] ? alt : zn1[4];
    double tz_spline = 0.0;
    const double factor = region_profile(*this, zb, xm, 1.0 + alpha, zn1, tn1, tgn1, 5, tz_spline);
    tz = tz_spline;
    if (xm == 0.0) return tz;
    result = factor;  // applied below to the density at za
  } else if (xm == 0.0) {
    return result;
  }
  // Diffusive density at z >= za from the lower boundary (Bates profile, closed form).
  const double glb = gsurf_ / std::pow(1.0 + zlb / re_, 2.0);
  const double gamma = xm * glb / (s2 * kGasConstant * tinf);
  double expl = std::exp(-s2 * gamma * zg2);
  if (expl > 50.0 || tt <= 0.0) expl = 50.0;
  const double at_za = dlb * std::pow(tlb / tt, 1.0 + alpha + gamma) * expl;
  if (alt >= za) return at_za;
  return at_za * result;
}

double Profiles::densm(double alt, double d0, double xm, double& tz, const TemperatureNodes& nodes) const {
  if (alt > kZn2_km[0]) return xm == 0.0 ? tz : d0;
  // Middle atmosphere: 72.5 km down to 32.5 km.
  const double z = alt > kZn2_km[3] ? alt : kZn2_km[3];
  double density = d0 * region_profile(*this, z, xm, 1.0, kZn2_km, nodes.tn2, nodes.tgn2, 4, tz);
  if (alt > kZn3_km[0]) return xm == 0.0 ? tz : density;
  // Lower atmosphere: 32.5 km to the ground.
  density *= region_profile(*this, alt, xm, 1.0, kZn3_km, nodes.tn3, nodes.tgn3, 5, tz);
  return xm == 0.0 ? tz : density;
}

double dnet(double dd, double dm, double zhm, double xmm, double xm) {
  const double a = zhm / (xmm - xm);
  if (!(dm > 0.0 && dd > 0.0)) {
    if (dd == 0.0 && dm == 0.0) dd = 1.0;
    if (dm == 0.0) return dd;
    if (dd == 0.0) return dm;
  }
  const double ylog = a * std::log(dm / dd);
  if (ylog < -10.0) return dd;
  if (ylog > 10.0) return dm;
  return dd * std::pow(1.0 + std::exp(ylog), 1.0 / a);
}

double ccor(double alt, double r, double h1, double zh) {
  const double e = (alt - zh) / h1;
  if (e > 70.0) return 1.0;
  if (e < -70.0) return std::exp(r);
  return std::exp(r / (1.0 + std::exp(e)));
}

double ccor2(double alt, double r, double h1, double zh, double h2) {
  const double e1 = (alt - zh) / h1;
  const double e2 = (alt - zh) / h2;
  if (e1 > 70.0 || e2 > 70.0) return 1.0;
  if (e1 < -70.0 && e2 < -70.0) return std::exp(r);
  return std::exp(r / (1.0 + 0.5 * (std::exp(e1) + std::exp(e2))));
}

void spline_second_derivatives(const double* x, const double* y, int n, double yp1, double ypn, double* y2) {
  double u[10];
  if (yp1 > 0.99e30) {
    y2[0] = 0.0;
    u[0] = 0.0;
  } else {
    y2[0] = -0.5;
    u[0] = (3.0 / (x[1] - x[0])) * ((y[1] - y[0]) / (x[1] - x[0]) - yp1);
  }
  for (int i = 1; i < n - 1; ++i) {
    const double sig = (x[i] - x[i - 1]) / (x[i + 1] - x[i - 1]);
    const double p = sig * y2[i - 1] + 2.0;
    y2[i] = (sig - 1.0) / p;
    u[i] = (6.0 * ((y[i + 1] - y[i]) / (x[i + 1] - x[i]) - (y[i] - y[i - 1]) / (x[i] - x[i - 1])) /
                (x[i + 1] - x[i - 1]) -
            sig * u[i - 1]) /
           p;
  }
  double qn = 0.0, un = 0.0;
  if (!(ypn > 0.99e30)) {
    qn = 0.5;
    un = (3.0 / (x[n - 1] - x[n - 2])) * (ypn - (y[n - 1] - y[n - 2]) / (x[n - 1] - x[n - 2]));
  }
  y2[n - 1] = (un - qn * u[n - 2]) / (qn * y2[n - 2] + 1.0);
  for (int k = n - 2; k >= 0; --k) y2[k] = y2[k] * y2[k + 1] + u[k];
}

double spline_value(const double* xa, const double* ya, const double* y2a, int n, double x) {
  int lo = 0, hi = n - 1;
  while (hi - lo > 1) {
    const int mid = (hi + lo) / 2;
    if (xa[mid] > x)
      hi = mid;
    else
      lo = mid;
  }
  const double h = xa[hi] - xa[lo];
  const double a = (xa[hi] - x) / h;
  const double b = (x - xa[lo]) / h;
  return a * ya[lo] + b * ya[hi] + ((a * a * a - a) * y2a[lo] + (b * b * b - b) * y2a[hi]) * h * h / 6.0;
}

double spline_integral(const double* xa, const double* ya, const double* y2a, int n, double x) {
  double sum = 0.0;
  for (int lo = 0, hi = 1; x > xa[lo] && hi < n; ++lo, ++hi) {
    const double xx = (hi < n - 1 && x >= xa[hi]) ? xa[hi] : x;
    const double h = xa[hi] - xa[lo];
    const double a = (xa[hi] - xx) / h;
    const double b = (xx - xa[lo]) / h;
    const double a2 = a * a, b2 = b * b;
    sum += ((1.0 - a2) * ya[lo] / 2.0 + b2 * ya[hi] / 2.0 +
            ((-(1.0 + a2 * a2) / 4.0 + a2 / 2.0) * y2a[lo] + (b2 * b2 / 4.0 - b2 / 2.0) * y2a[hi]) * h * h /
                6.0) *
           h;
  }
  return sum;
}

}  // namespace kessler::nrlmsise00
