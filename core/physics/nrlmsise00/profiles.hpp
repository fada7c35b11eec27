// The vertical structure of NRLMSISE-00 (Picone et al. 2002; the profiles of Hedin's MSIS-86/MSISE-90):
//  - above zlb = 120 km the Bates-Walker temperature T(z) = T_inf - (T_inf - T_lb) exp(-s zeta(z, zlb)),
//    zeta the geopotential height, and the diffusive density from hydrostatic equilibrium with thermal
//    diffusion (densu);
//  - below 120 km the temperature is 1/T interpolated by cubic splines in geopotential height through
//    nodes (120..72.5 km, 72.5..32.5 km, 32.5..0 km), and the density the integral of the hydrostatic
//    equation along the spline (densu below zn1[0], densm in the middle and lower atmosphere);
//  - the turbopause mixing (dnet) and the chemistry/flux corrections (ccor, ccor2).
// Gravity and the effective Earth radius depend on latitude (Profiles::at_latitude).
#pragma once

namespace kessler::nrlmsise00 {

// Temperature nodes of the three spline regions: lower thermosphere (tn1, 5 nodes from 120 to 72.5 km),
// middle atmosphere (tn2, 4 nodes 72.5..32.5 km) and lower atmosphere (tn3, 5 nodes 32.5..0 km), each
// with the temperature gradients at its two ends (tgn).
struct TemperatureNodes {
  double tn1[5] = {}, tgn1[2] = {};
  double tn2[4] = {}, tgn2[2] = {};
  double tn3[5] = {}, tgn3[2] = {};
};

inline constexpr double kZn1_km[5] = {120.0, 110.0, 100.0, 90.0, 72.5};  // zn1[0] is set to pdl[1][15]
inline constexpr double kZn2_km[4] = {72.5, 55.0, 45.0, 32.5};
inline constexpr double kZn3_km[5] = {32.5, 20.0, 15.0, 10.0, 0.0};

class Profiles {
 public:
  // Surface gravity [cm/s^2] and effective radius [km] at the latitude (the model's formula).
  static Profiles at_latitude(double latitude_deg);

  double gsurf() const { return gsurf_; }
  double re() const { return re_; }

  // Geopotential height difference of z over zl [km].
  double zeta(double z, double zl) const { return (z - zl) * (re_ + zl) / (re_ + z); }
  // Scale height [km] of molecular mass xm at temperature temp at altitude alt.
  double scale_height(double alt, double xm, double temp) const;

  // Density at alt of a species of molecular mass xm (or, with xm == 0, the temperature there), from
  // its density dlb at the lower boundary zlb; tinf, tlb, s2 the Bates profile; alpha the thermal
  // diffusion coefficient; tz receives the temperature at alt. zn1[0]..zn1[4], tn1, tgn1: the lower
  // thermosphere's nodes (tn1[0], tgn1[0] are written: the profile's value and slope at zn1[0]).
  double densu(double alt, double dlb, double tinf, double tlb, double xm, double alpha, double& tz,
               double zlb, double s2, const double zn1[5], double tn1[5], double tgn1[2]) const;
  // Density below zn2[0] (72.5 km) from its value d0 there (or, with xm == 0, the temperature).
  double densm(double alt, double d0, double xm, double& tz, const TemperatureNodes& nodes) const;

 private:
  double gsurf_ = 0.0;
  double re_ = 0.0;
};

// Turbopause: the net density from the diffusive dd and mixed dm densities (zhm the transition scale,
// xmm the mean mass, xm the species' mass).
double dnet(double dd, double dm, double zhm, double xmm, double xm);
// Chemistry/dissociation correction exp(r / (1 + exp((alt - zh)/h1))) and its two-scale form.
double ccor(double alt, double r, double h1, double zh);
double ccor2(double alt, double r, double h1, double zh, double h2);

// Natural cubic splines on n <= 10 nodes (derivatives yp1, ypn at the ends, > 0.99e30 for natural):
// the second derivatives, the value at x, and the integral from xa[0] to x.
void spline_second_derivatives(const double* x, const double* y, int n, double yp1, double ypn, double* y2);
double spline_value(const double* xa, const double* ya, const double* y2a, int n, double x);
double spline_integral(const double* xa, const double* ya, const double* y2a, int n, double x);

}  // namespace kessler::nrlmsise00
