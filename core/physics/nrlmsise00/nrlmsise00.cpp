#include "core/physics/nrlmsise00/nrlmsise00.hpp"

#include <cmath>

#include "core/physics/nrlmsise00/coefficients.hpp"
#include "core/physics/nrlmsise00/profiles.hpp"

namespace kessler {
namespace nrlmsise00 {
namespace {

constexpr double kDegToRad = 1.74533e-2;
constexpr double kDayRate = 1.72142e-2;
constexpr double kAmu_g = 1.66e-24;  // the model's atomic mass unit [g]

// Densities in the model's order: He, O, N2, O2, Ar, (total), H, N, anomalous O [cm^-3; g/cm^3].
struct Densities {
  double d[9] = {};
  double t_exo = 0, t_alt = 0;
};

double mass_density(const double* d) {
  return kAmu_g * (4.0 * d[0] + 16.0 * d[1] + 28.0 * d[2] + 32.0 * d[3] + 40.0 * d[4] + d[6] + 14.0 * d[7]);
}

// Everything the thermosphere's species share at one point.
struct Thermosphere {
  const ModelInput& in;
  const Switches& s;
  const Profiles& pr;
  TemperatureNodes& nodes;
  double zn1[5];
  double tinf = 0, tlb = 0, slope = 0;
  double xmm = 0;    // mean molecular mass below the turbopause
  double zhm28 = 0;  // turbopause transition scale
  double b28 = 0;    // N2's mixed density at its turbopause
  double dm28 = 0;   // N2's mixed density at the altitude

  double densu(double z, double dlb, double xm, double alpha, double& tz) const {
    return pr.densu(z, dlb, tinf, tlb, xm, alpha, tz, ptm[5], slope, zn1, nodes.tn1, nodes.tgn1);
  }
  double densu(double z, double dlb, double xm, double alpha) const {
    double tz = 0.0;
    return densu(z, dlb, xm, alpha, tz);
  }
  double flux_factor() const { return 1.0 + s.sw[1] * pdl[0][23] * (in.f107_avg - 150.0); }
};

// One minor species (He, O, O2, Ar, H, N): diffusive density at z from its 120 km value, and below
// `mix_top` the turbopause blend with the mixed profile and its own corrections (the model's layout of
// coefficients: pd row, pdm row, mass, thermal diffusion, mixing altitude).
struct SpeciesSpec {
  int pd_row, pdm_row;
  double mass, alpha, mix_top;
  bool mix_inclusive;  // z <= mix_top (He uses z < mix_top)
};

constexpr SpeciesSpec kSpecies[] = {
    {0, 0, 4.0, -0.38, 200.0, false},  // He
    {1, 1, 16.0, 0.0, 300.0, true},    // O
    {2, 2, 28.0, 0.0, 160.0, true},    // N2 (its own code below)
    {4, 3, 32.0, 0.0, 250.0, true},    // O2
    {5, 4, 40.0, 0.17, 240.0, true},   // Ar
    {0, 0, 0.0, 0.0, 0.0, true},       // (total)
    {6, 5, 1.0, -0.38, 320.0, true},   // H
    {7, 6, 14.0, 0.0, 450.0, true},    // N
    {8, 7, 16.0, 0.0, 0.0, true},      // anomalous O (its own code below)
};

// g: the species' density variation at the lower boundary (globe7 of its pd row).
// turbopause: the column's cache of the species' mixed density at its turbopause height (it depends on the
// altitude only through the regime the model picks: above/below 120, 72.5 and 300 km).
double species(Thermosphere& th, const SpeciesSpec& sp, double g, double z, int which,
               TurbopauseCache& turbopause) {
  const double* pdm_row = pdm[sp.pdm_row];
  const double db = pdm_row[0] * std::exp(g) * pd[sp.pd_row][0];
  double d = th.densu(z, db, sp.mass, sp.alpha);
  const bool mixes = th.s.sw[15] != 0.0 && (sp.mix_inclusive ? z <= sp.mix_top : z < sp.mix_top);
  if (mixes) {
    if (!turbopause.has[which]) {
      turbopause.b[which] = th.densu(pdm_row[2], db, sp.mass - th.xmm, sp.alpha - 1.0);
      turbopause.has[which] = true;
    }
    const double b = turbopause.b[which];
    const double dm = th.densu(z, b, th.xmm, 0.0);
    d = dnet(d, dm, th.zhm28, th.xmm, sp.mass);
    switch (which) {
      case 0:  // He
        d *= ccor(z, std::log(th.b28 * pdm_row[1] / b), pdm_row[5] * pdl[1][1], pdm_row[4] * pdl[1][0]);
        break;
      case 1:  // O: mixing-ratio correction with two scales, then chemistry
        d *= ccor2(z, pdm_row[1] * pdl[1][16] * th.flux_factor(), pdm_row[5] * pdl[1][3],
                   pdm_row[4] * pdl[1][2], pdm_row[5] * pdl[1][4]);
        d *= ccor(z, pdm_row[3] * pdl[1][14], pdm_row[7] * pdl[1][13], pdm_row[6] * pdl[1][12]);
        break;
      case 3:  // O2
        d *= ccor(z, std::log(th.b28 * pdm_row[1] / b), pdm_row[5] * pdl[1][7], pdm_row[4] * pdl[1][6]);
        break;
      case 4:  // Ar
        d *= ccor(z, std::log(th.b28 * pdm_row[1] / b), pdm_row[5] * pdl[1][9], pdm_row[4] * pdl[1][8]);
        break;
      case 6:  // H
        d *= ccor(z, std::log(th.b28 * pdm_row[1] * std::sqrt(pdl[1][17] * pdl[1][17]) / b),
                  pdm_row[5] * pdl[1][11], pdm_row[4] * pdl[1][10]);
        d *= ccor(z, pdm_row[3] * pdl[1][20], pdm_row[7] * pdl[1][19], pdm_row[6] * pdl[1][18]);
        break;
      case 7:  // N
        d *= ccor(z, std::log(th.b28 * pdm_row[1] * std::sqrt(pdl[0][2] * pdl[0][2]) / b),
                  pdm_row[5] * pdl[0][1], pdm_row[4] * pdl[0][0]);
        d *= ccor(z, pdm_row[3] * pdl[0][5], pdm_row[7] * pdl[0][4], pdm_row[6] * pdl[0][3]);
        break;
      default:
        break;
    }
  }
  // O2's departure from diffusive equilibrium applies at every altitude.
  if (which == 3 && th.s.sw[15] != 0.0)
    d *= ccor2(z, pdm_row[3] * pdl[1][23] * th.flux_factor(), pdm_row[7] * pdl[1][22],
               pdm_row[6] * pdl[1][21], pdm_row[7] * pdl[0][22]);
  return d;
}

// The lower thermosphere's temperature nodes (110, 100, 90, 72.5 km) and the gradient at 72.5 km; the
// model varies them only below 300 km (`vary`), above it takes their means.
TemperatureNodes lower_thermosphere_nodes(const ModelInput& in, const Switches& s, const ExpansionState& ex,
                                          bool vary) {
  TemperatureNodes n;
  auto g = [&](const double* p, double sw) { return vary ? sw * glob7s(p, in, s, ex) : 0.0; };
  n.tn1[1] = ptm[6] * ptl[0][0] / (1.0 - g(ptl[0], s.sw[18]));
  n.tn1[2] = ptm[2] * ptl[1][0] / (1.0 - g(ptl[1], s.sw[18]));
  n.tn1[3] = ptm[7] * ptl[2][0] / (1.0 - g(ptl[2], s.sw[18]));
  n.tn1[4] = ptm[4] * ptl[3][0] / (1.0 - g(ptl[3], s.sw[18] * s.sw[20]));
  n.tgn1[1] = ptm[8] * pma[8][0] * (1.0 + g(pma[8], s.sw[18] * s.sw[20])) * n.tn1[4] * n.tn1[4] /
              std::pow(ptm[4] * ptl[3][0], 2.0);
  return n;
}

}  // namespace

// The thermosphere's altitude-independent part (the expansions of the model's gts7), in the order the
// model evaluates them (glob7s reads the magnetic term of the last globe7 before it).
ColumnTerms::ColumnTerms(const ModelInput& in, const Switches& s)
    : input(in), switches(s), profiles(Profiles::at_latitude(s.sw[2] == 0.0 ? 45.0 : in.latitude_deg)) {
  tinf_varying = ptm[0] * pt[0] * (1.0 + s.sw[16] * globe7(pt, in, s, ex));
  tinf_mean = ptm[0] * pt[0];
  g0_varying = ptm[3] * ps[0] * (1.0 + s.sw[19] * globe7(ps, in, s, ex));
  g0_mean = ptm[3] * ps[0];
  tlb = ptm[1] * (1.0 + s.sw[17] * globe7(pd[3], in, s, ex)) * pd[3][0];
  nodes_low = lower_thermosphere_nodes(in, s, ex, true);
  nodes_high = lower_thermosphere_nodes(in, s, ex, false);
  for (int k : {2, 0, 1, 3, 4, 6, 7, 8}) g[k] = s.sw[21] * globe7(pd[kSpecies[k].pd_row], in, s, ex);
}

namespace {

// The thermosphere (the model's gts7) at altitude z > 72.5 km of a column. Also returns N2's mixed
// density at z (the whole model continues it below 72.5 km) and the nodes used.
Densities thermosphere(const ColumnTerms& c, double z, double& dm28, TemperatureNodes& nodes) {
  Densities out;
  nodes = z < 300.0 ? c.nodes_low : c.nodes_high;
  const Switches& s = c.switches;
  const ModelInput& in = c.input;
  Thermosphere th{in, s, c.profiles, nodes, {pdl[1][15], kZn1_km[1], kZn1_km[2], kZn1_km[3], kZn1_km[4]}};
  // Exospheric temperature, gradient and temperature at the lower boundary (120 km).
  th.tinf = z > th.zn1[0] ? c.tinf_varying : c.tinf_mean;
  const double g0 = z > th.zn1[4] ? c.g0_varying : c.g0_mean;
  th.tlb = c.tlb;
  th.slope = g0 / (th.tinf - th.tlb);
  out.t_exo = th.tinf;
  th.xmm = pdm[2][4];

  // N2: the reference for every other species' turbopause.
  const double zhf = pdl[1][24] * (1.0 + s.sw[5] * pdl[0][24] * std::sin(kDegToRad * in.latitude_deg) *
                                             std::cos(kDayRate * (in.day_of_year - pt[13])));
  const double db28 = pdm[2][0] * std::exp(c.g[2]) * pd[2][0];
  out.d[2] = th.densu(z, db28, 28.0, 0.0);
  th.zhm28 = pdm[2][3] * pdl[1][5];
  const int regime = (z > th.zn1[0] ? 1 : 0) + (z > th.zn1[4] ? 2 : 0) + (z < 300.0 ? 4 : 0);
  TurbopauseCache& turbopause = c.turbopause[regime];
  if (!turbopause.has[2]) {
    turbopause.b[2] = th.densu(pdm[2][2] * zhf, db28, 28.0 - th.xmm, -1.0);
    turbopause.has[2] = true;
  }
  th.b28 = turbopause.b[2];
  if (s.sw[15] != 0.0 && z <= 160.0) {
    th.dm28 = th.densu(z, th.b28, th.xmm, 0.0);
    out.d[2] = dnet(out.d[2], th.dm28, th.zhm28, th.xmm, 28.0);
  }
  dm28 = th.dm28;
  for (int k : {0, 1, 3, 4, 6, 7}) out.d[k] = species(th, kSpecies[k], c.g[k], z, k, turbopause);

  // Anomalous oxygen: a hot isothermal component with its own scale-height transition.
  const double db16h = pdm[7][0] * std::exp(c.g[8]) * pd[8][0];
  const double tho = pdm[7][9] * pdl[0][6];
  double t_unused = 0.0;
  const double dd = c.profiles.densu(z, db16h, tho, tho, 16.0, 0.0, t_unused, ptm[5], th.slope, th.zn1,
                                     nodes.tn1, nodes.tgn1);
  const double zsht = pdm[7][5];
  const double zmho = pdm[7][4];
  const double zsho = c.profiles.scale_height(zmho, 16.0, tho);
  out.d[8] = dd * std::exp(-zsht / zsho * (std::exp(-(z - zmho) / zsht) - 1.0));

  out.d[5] = mass_density(out.d);
  th.densu(std::fabs(z), 1.0, 0.0, 0.0, out.t_alt);
  return out;
}

// The middle and lower atmosphere's temperature nodes (the model's gtd7 below 72.5 km).
void middle_atmosphere_nodes(const ModelInput& in, const Switches& s, const ExpansionState& ex,
                             TemperatureNodes& n) {
  auto g = [&](int row, double sw) { return sw * glob7s(pma[row], in, s, ex); };
  n.tgn2[0] = n.tgn1[1];
  n.tn2[0] = n.tn1[4];
  n.tn2[1] = pma[0][0] * pavgm[0] / (1.0 - g(0, s.sw[20]));
  n.tn2[2] = pma[1][0] * pavgm[1] / (1.0 - g(1, s.sw[20]));
  n.tn2[3] = pma[2][0] * pavgm[2] / (1.0 - g(2, s.sw[20] * s.sw[22]));
  n.tgn2[1] = pavgm[8] * pma[9][0] * (1.0 + g(9, s.sw[20] * s.sw[22])) * n.tn2[3] * n.tn2[3] /
              std::pow(pma[2][0] * pavgm[2], 2.0);
  n.tn3[0] = n.tn2[3];
  if (in.altitude_km < kZn3_km[0]) {
    n.tgn3[0] = n.tgn2[1];
    for (int k = 1; k <= 4; ++k) n.tn3[k] = pma[2 + k][0] * pavgm[2 + k] / (1.0 - g(2 + k, s.sw[22]));
    n.tgn3[1] = pma[7][0] * pavgm[7] * (1.0 + g(7, s.sw[22])) * n.tn3[4] * n.tn3[4] /
                std::pow(pma[6][0] * pavgm[6], 2.0);
  }
}

Densities whole_model(const ModelInput& input, const Switches& s) {
  constexpr double kZmix = 62.5;
  // The thermosphere at the altitude, or at 72.5 km for the profile below.
  ModelInput at = input;
  at.altitude_km = input.altitude_km > kZn2_km[0] ? input.altitude_km : kZn2_km[0];
  const ColumnTerms column(at, s);
  double dm28 = 0.0;
  TemperatureNodes nodes;
  const Densities top = thermosphere(column, at.altitude_km, dm28, nodes);
  if (input.altitude_km >= kZn2_km[0]) return top;

  const Profiles& pr = column.profiles;
  middle_atmosphere_nodes(input, s, column.ex, nodes);
  Densities out;
  out.t_exo = top.t_exo;
  const double z = input.altitude_km;
  // Linear transition to full mixing below 72.5 km, complete at kZmix.
  const double dmc = z > kZmix ? 1.0 - (kZn2_km[0] - z) / (kZn2_km[0] - kZmix) : 0.0;
  const double dz28 = top.d[2];
  double tz = 0.0;
  out.d[2] = pr.densm(z, dm28, pdm[2][4], tz, nodes) * (1.0 + (top.d[2] / dm28 - 1.0) * dmc);
  auto mixed = [&](int k, double ratio) {
    const double dmr = top.d[k] / (dz28 * ratio) - 1.0;
    return out.d[2] * ratio * (1.0 + dmr * dmc);
  };
  out.d[0] = mixed(0, pdm[0][1]);
  out.d[3] = mixed(3, pdm[3][1]);
  out.d[4] = mixed(4, pdm[4][1]);
  out.d[5] = mass_density(out.d);
  out.t_alt = pr.densm(z, 1.0, 0.0, tz, nodes);
  return out;
}

MsisOutput to_output(const Densities& d) {
  constexpr double kPerCm3 = 1.0e6;   // cm^-3 -> m^-3
  constexpr double kGPerCm3 = 1.0e3;  // g/cm^3 -> kg/m^3
  MsisOutput out;
  out.he = d.d[0] * kPerCm3;
  out.o = d.d[1] * kPerCm3;
  out.n2 = d.d[2] * kPerCm3;
  out.o2 = d.d[3] * kPerCm3;
  out.ar = d.d[4] * kPerCm3;
  out.h = d.d[6] * kPerCm3;
  out.n = d.d[7] * kPerCm3;
  out.anomalous_o = d.d[8] * kPerCm3;
  out.rho_kg_m3 = d.d[5] * kGPerCm3;
  out.rho_drag_kg_m3 = (d.d[5] + kAmu_g * 16.0 * d.d[8]) * kGPerCm3;
  out.exospheric_temperature_k = d.t_exo;
  out.temperature_k = d.t_alt;
  return out;
}

}  // namespace
}  // namespace nrlmsise00

MsisOutput nrlmsise00_density(const MsisInput& input, const nrlmsise00::Switches& switches) {
  return nrlmsise00::to_output(nrlmsise00::whole_model(input, switches));
}

MsisOutput nrlmsise00::ColumnTerms::at(double altitude_km) const {
  double dm28 = 0.0;
  TemperatureNodes nodes;
  return to_output(thermosphere(*this, altitude_km, dm28, nodes));
}

}  // namespace kessler
