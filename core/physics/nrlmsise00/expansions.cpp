#include "core/physics/nrlmsise00/expansions.hpp"

#include <cmath>
#include <stdexcept>

namespace kessler::nrlmsise00 {
namespace {

// The model's own rounded constants (degrees to radians, day-of-year and time-of-day angular rates).
constexpr double kDegToRad = 1.74533e-2;
constexpr double kDayRate = 1.72142e-2;  // 2 pi / 365
constexpr double kHourRate = 0.2618;     // 2 pi / 24
constexpr double kSecRate = 7.2722e-5;   // 2 pi / 86400

// Associated Legendre functions P_n^m(sin lat) as the model normalises them (plg[m][n]).
void legendre(double latitude_deg, double plg[4][9]) {
  const double c = std::sin(latitude_deg * kDegToRad);
  const double s = std::cos(latitude_deg * kDegToRad);
  const double c2 = c * c, c4 = c2 * c2, s2 = s * s;
  plg[0][1] = c;
  plg[0][2] = 0.5 * (3.0 * c2 - 1.0);
  plg[0][3] = 0.5 * (5.0 * c * c2 - 3.0 * c);
  plg[0][4] = (35.0 * c4 - 30.0 * c2 + 3.0) / 8.0;
  plg[0][5] = (63.0 * c2 * c2 * c - 70.0 * c2 * c + 15.0 * c) / 8.0;
  plg[0][6] = (11.0 * c * plg[0][5] - 5.0 * plg[0][4]) / 6.0;
  plg[1][1] = s;
  plg[1][2] = 3.0 * c * s;
  plg[1][3] = 1.5 * (5.0 * c2 - 1.0) * s;
  plg[1][4] = 2.5 * (7.0 * c2 * c - 3.0 * c) * s;
  plg[1][5] = 1.875 * (21.0 * c4 - 14.0 * c2 + 1.0) * s;
  plg[1][6] = (11.0 * c * plg[1][5] - 6.0 * plg[1][4]) / 5.0;
  plg[2][2] = 3.0 * s2;
  plg[2][3] = 15.0 * s2 * c;
  plg[2][4] = 7.5 * (7.0 * c2 - 1.0) * s2;
  plg[2][5] = 3.0 * c * plg[2][4] - 2.0 * plg[2][3];
  plg[2][6] = (11.0 * c * plg[2][5] - 7.0 * plg[2][4]) / 4.0;
  plg[2][7] = (13.0 * c * plg[2][6] - 8.0 * plg[2][5]) / 5.0;
  plg[3][3] = 15.0 * s2 * s;
  plg[3][4] = 105.0 * s2 * s * c;
  plg[3][5] = (9.0 * c * plg[3][4] - 7.0 * plg[3][3]) / 2.0;
  plg[3][6] = (11.0 * c * plg[3][5] - 8.0 * plg[3][4]) / 3.0;
}

// The saturating Ap function of the 3-hour history (MSIS-86 eq. A24a) and its weighted sum.
double ap_function(double a, double p24, double p25) {
  const double k = std::sqrt(p24 * p24);
  return a - 4.0 + (p25 - 1.0) * (a - 4.0 + (std::exp(-k * (a - 4.0)) - 1.0) / k);
}

double ap_history_term(double decay, double p24, double p25, const std::array<double, 7>& a) {
  const double norm = 1.0 + (1.0 - std::pow(decay, 19.0)) / (1.0 - decay) * std::sqrt(decay);
  const double recent = ap_function(a[1], p24, p25) +
                        (ap_function(a[2], p24, p25) * decay + ap_function(a[3], p24, p25) * decay * decay +
                         ap_function(a[4], p24, p25) * std::pow(decay, 3.0) +
                         (ap_function(a[5], p24, p25) * std::pow(decay, 4.0) +
                          ap_function(a[6], p24, p25) * std::pow(decay, 12.0)) *
                             (1.0 - std::pow(decay, 8.0)) / (1.0 - decay));
  return recent / norm;
}

// Magnetic activity term t[8] and the longitude/UT magnetic term t[12] of globe7 (which, being the
// model's own layout of coefficients, is long but one expression per term).
void magnetic_terms(const double* p, const ModelInput& in, const Switches& s, ExpansionState& st, double cd14,
                    double& t8, double& t12) {
  const auto& plg = st.plg;
  const auto& sw = s.sw;
  const auto& swc = s.swc;
  const double tloc = in.local_solar_time_h;
  t8 = 0.0;
  t12 = 0.0;
  const bool longitude = sw[10] != 0.0 && sw[13] != 0.0 && in.longitude_deg > -1000.0;
  if (sw[9] == -1.0) {
    if (p[51] == 0.0) return;
    double decay = std::exp(-10800.0 * std::sqrt(p[51] * p[51]) /
                            (1.0 + p[138] * (45.0 - std::sqrt(in.latitude_deg * in.latitude_deg))));
    if (decay > 0.99999) decay = 0.99999;
    const double p24 = p[24] < 1.0e-4 ? 1.0e-4 : p[24];
    st.apt = ap_history_term(decay, p24, p[25], in.ap_history);
    const double a = st.apt;
    t8 = a * (p[50] + p[96] * plg[0][2] + p[54] * plg[0][4] +
              (p[125] * plg[0][1] + p[126] * plg[0][3] + p[127] * plg[0][5]) * cd14 * swc[5] +
              (p[128] * plg[1][1] + p[129] * plg[1][3] + p[130] * plg[1][5]) * swc[7] *
                  std::cos(kHourRate * (tloc - p[131])));
    if (longitude)
      t12 = a * swc[11] * (1.0 + p[132] * plg[0][1]) *
                ((p[52] * plg[1][2] + p[98] * plg[1][4] + p[67] * plg[1][6]) *
                 std::cos(kDegToRad * (in.longitude_deg - p[97]))) +
            a * swc[11] * swc[5] * (p[133] * plg[1][1] + p[134] * plg[1][3] + p[135] * plg[1][5]) * cd14 *
                std::cos(kDegToRad * (in.longitude_deg - p[136])) +
            a * swc[12] * (p[55] * plg[0][1] + p[56] * plg[0][3] + p[57] * plg[0][5]) *
                std::cos(kSecRate * (in.ut_s - p[58]));
    return;
  }
  const double apd = in.ap - 4.0;
  const double p44 = p[43] < 0.0 ? 1.0e-5 : p[43];
  const double p45 = p[44];
  st.apdf = apd + (p45 - 1.0) * (apd + (std::exp(-p44 * apd) - 1.0) / p44);
  const double a = st.apdf;
  if (sw[9] != 0.0)
    t8 = a * (p[32] + p[45] * plg[0][2] + p[34] * plg[0][4] +
              (p[100] * plg[0][1] + p[101] * plg[0][3] + p[102] * plg[0][5]) * cd14 * swc[5] +
              (p[121] * plg[1][1] + p[122] * plg[1][3] + p[123] * plg[1][5]) * swc[7] *
                  std::cos(kHourRate * (tloc - p[124])));
  if (longitude)
    t12 = a * swc[11] * (1.0 + p[120] * plg[0][1]) *
              ((p[60] * plg[1][2] + p[61] * plg[1][4] + p[62] * plg[1][6]) *
               std::cos(kDegToRad * (in.longitude_deg - p[63]))) +
          a * swc[11] * swc[5] * (p[115] * plg[1][1] + p[116] * plg[1][3] + p[117] * plg[1][5]) * cd14 *
              std::cos(kDegToRad * (in.longitude_deg - p[118])) +
          a * swc[12] * (p[83] * plg[0][1] + p[84] * plg[0][3] + p[85] * plg[0][5]) *
              std::cos(kSecRate * (in.ut_s - p[75]));
}

}  // namespace

Switches Switches::from(const std::array<int, 24>& settings) {
  Switches s;
  for (std::size_t i = 0; i < 24; ++i) {
    if (i == 9) {
      s.sw[i] = settings[i];
      s.swc[i] = settings[i];
    } else {
      s.sw[i] = settings[i] == 1 ? 1.0 : 0.0;
      s.swc[i] = settings[i] > 0 ? 1.0 : 0.0;
    }
  }
  return s;
}

Switches Switches::all_on() {
  std::array<int, 24> settings;
  settings.fill(1);
  settings[0] = 0;
  return from(settings);
}

// The model's layout of terms t[0..13] (one per kind of variation), summed with the switches.
double globe7(const double* p, const ModelInput& in, const Switches& s, ExpansionState& st) {
  const auto& sw = s.sw;
  const auto& swc = s.swc;
  double t[14] = {};
  legendre(in.latitude_deg, st.plg);
  const auto& plg = st.plg;
  const double tloc = in.local_solar_time_h;
  if (sw[7] != 0.0 || sw[8] != 0.0 || sw[14] != 0.0) {
    st.stloc = std::sin(kHourRate * tloc);
    st.ctloc = std::cos(kHourRate * tloc);
    st.s2tloc = std::sin(2.0 * kHourRate * tloc);
    st.c2tloc = std::cos(2.0 * kHourRate * tloc);
    st.s3tloc = std::sin(3.0 * kHourRate * tloc);
    st.c3tloc = std::cos(3.0 * kHourRate * tloc);
  }
  const double doy = in.day_of_year;
  const double cd32 = std::cos(kDayRate * (doy - p[31]));
  const double cd18 = std::cos(2.0 * kDayRate * (doy - p[17]));
  const double cd14 = std::cos(kDayRate * (doy - p[13]));
  const double cd39 = std::cos(2.0 * kDayRate * (doy - p[38]));

  // Solar flux.
  const double df = in.f107 - in.f107_avg;
  st.dfa = in.f107_avg - 150.0;
  const double dfa = st.dfa;
  t[0] = p[19] * df * (1.0 + p[59] * dfa) + p[20] * df * df + p[21] * dfa + p[29] * dfa * dfa;
  const double f1 = 1.0 + (p[47] * dfa + p[19] * df + p[20] * df * df) * swc[1];
  const double f2 = 1.0 + (p[49] * dfa + p[19] * df + p[20] * df * df) * swc[1];
  // Time independent; annual and semiannual, symmetric and asymmetric.
  t[1] = (p[1] * plg[0][2] + p[2] * plg[0][4] + p[22] * plg[0][6]) + (p[14] * plg[0][2]) * dfa * swc[1] +
         p[26] * plg[0][1];
  t[2] = p[18] * cd32;
  t[3] = (p[15] + p[16] * plg[0][2]) * cd18;
  t[4] = f1 * (p[9] * plg[0][1] + p[10] * plg[0][3]) * cd14;
  t[5] = p[37] * plg[0][1] * cd39;
  // Diurnal, semidiurnal, terdiurnal.
  if (sw[7] != 0.0) {
    const double t71 = (p[11] * plg[1][2]) * cd14 * swc[5];
    const double t72 = (p[12] * plg[1][2]) * cd14 * swc[5];
    t[6] = f2 * ((p[3] * plg[1][1] + p[4] * plg[1][3] + p[27] * plg[1][5] + t71) * st.ctloc +
                 (p[6] * plg[1][1] + p[7] * plg[1][3] + p[28] * plg[1][5] + t72) * st.stloc);
  }
  if (sw[8] != 0.0) {
    const double t81 = (p[23] * plg[2][3] + p[35] * plg[2][5]) * cd14 * swc[5];
    const double t82 = (p[33] * plg[2][3] + p[36] * plg[2][5]) * cd14 * swc[5];
    t[7] = f2 * ((p[5] * plg[2][2] + p[41] * plg[2][4] + t81) * st.c2tloc +
                 (p[8] * plg[2][2] + p[42] * plg[2][4] + t82) * st.s2tloc);
  }
  if (sw[14] != 0.0) {
    t[13] = f2 * ((p[39] * plg[3][3] + (p[93] * plg[3][4] + p[46] * plg[3][6]) * cd14 * swc[5]) * st.s3tloc +
                  (p[40] * plg[3][3] + (p[94] * plg[3][4] + p[48] * plg[3][6]) * cd14 * swc[5]) * st.c3tloc);
  }
  // Magnetic activity (t[8]) and its longitude/UT part (t[12]).
  magnetic_terms(p, in, s, st, cd14, t[8], t[12]);
  if (sw[10] != 0.0 && in.longitude_deg > -1000.0) {
    const double lon = kDegToRad * in.longitude_deg;
    if (sw[11] != 0.0) {  // longitude
      t[10] = (1.0 + p[80] * dfa * swc[1]) *
              ((p[64] * plg[1][2] + p[65] * plg[1][4] + p[66] * plg[1][6] + p[103] * plg[1][1] +
                p[104] * plg[1][3] + p[105] * plg[1][5] +
                swc[5] * (p[109] * plg[1][1] + p[110] * plg[1][3] + p[111] * plg[1][5]) * cd14) *
                   std::cos(lon) +
               (p[90] * plg[1][2] + p[91] * plg[1][4] + p[92] * plg[1][6] + p[106] * plg[1][1] +
                p[107] * plg[1][3] + p[108] * plg[1][5] +
                swc[5] * (p[112] * plg[1][1] + p[113] * plg[1][3] + p[114] * plg[1][5]) * cd14) *
                   std::sin(lon));
    }
    if (sw[12] != 0.0) {  // universal time, and UT mixed with longitude
      t[11] = (1.0 + p[95] * plg[0][1]) * (1.0 + p[81] * dfa * swc[1]) *
              (1.0 + p[119] * plg[0][1] * swc[5] * cd14) *
              ((p[68] * plg[0][1] + p[69] * plg[0][3] + p[70] * plg[0][5]) *
               std::cos(kSecRate * (in.ut_s - p[71])));
      t[11] += swc[11] * (p[76] * plg[2][3] + p[77] * plg[2][5] + p[78] * plg[2][7]) *
               std::cos(kSecRate * (in.ut_s - p[79]) + 2.0 * lon) * (1.0 + p[137] * dfa * swc[1]);
    }
  }
  double g = p[30];
  for (int i = 0; i < 14; ++i) g += std::fabs(sw[static_cast<std::size_t>(i) + 1]) * t[i];
  return g;
}

double glob7s(const double* p, const ModelInput& in, const Switches& s, const ExpansionState& st) {
  if (p[99] != 2.0) throw std::logic_error("nrlmsise00::glob7s: not a middle-atmosphere parameter set");
  const auto& sw = s.sw;
  const auto& swc = s.swc;
  const auto& plg = st.plg;
  double t[14] = {};
  const double doy = in.day_of_year;
  const double cd32 = std::cos(kDayRate * (doy - p[31]));
  const double cd18 = std::cos(2.0 * kDayRate * (doy - p[17]));
  const double cd14 = std::cos(kDayRate * (doy - p[13]));
  const double cd39 = std::cos(2.0 * kDayRate * (doy - p[38]));
  t[0] = p[21] * st.dfa;
  t[1] = p[1] * plg[0][2] + p[2] * plg[0][4] + p[22] * plg[0][6] + p[26] * plg[0][1] + p[14] * plg[0][3] +
         p[59] * plg[0][5];
  t[2] = (p[18] + p[47] * plg[0][2] + p[29] * plg[0][4]) * cd32;
  t[3] = (p[15] + p[16] * plg[0][2] + p[30] * plg[0][4]) * cd18;
  t[4] = (p[9] * plg[0][1] + p[10] * plg[0][3] + p[20] * plg[0][5]) * cd14;
  t[5] = (p[37] * plg[0][1]) * cd39;
  if (sw[7] != 0.0) {
    const double t71 = p[11] * plg[1][2] * cd14 * swc[5];
    const double t72 = p[12] * plg[1][2] * cd14 * swc[5];
    t[6] = ((p[3] * plg[1][1] + p[4] * plg[1][3] + t71) * st.ctloc +
            (p[6] * plg[1][1] + p[7] * plg[1][3] + t72) * st.stloc);
  }
  if (sw[8] != 0.0) {
    const double t81 = (p[23] * plg[2][3] + p[35] * plg[2][5]) * cd14 * swc[5];
    const double t82 = (p[33] * plg[2][3] + p[36] * plg[2][5]) * cd14 * swc[5];
    t[7] = ((p[5] * plg[2][2] + p[41] * plg[2][4] + t81) * st.c2tloc +
            (p[8] * plg[2][2] + p[42] * plg[2][4] + t82) * st.s2tloc);
  }
  if (sw[14] != 0.0) t[13] = p[39] * plg[3][3] * st.s3tloc + p[40] * plg[3][3] * st.c3tloc;
  if (sw[9] == 1.0) t[8] = st.apdf * (p[32] + p[45] * plg[0][2] * swc[2]);
  if (sw[9] == -1.0) t[8] = (p[50] * st.apt + p[96] * plg[0][2] * st.apt * swc[2]);
  if (sw[10] != 0.0 && sw[11] != 0.0 && in.longitude_deg > -1000.0) {
    const double lon = kDegToRad * in.longitude_deg;
    t[10] = (1.0 +
             plg[0][1] * (p[80] * swc[5] * std::cos(kDayRate * (doy - p[81])) +
                          p[85] * swc[6] * std::cos(2.0 * kDayRate * (doy - p[86]))) +
             p[83] * swc[3] * std::cos(kDayRate * (doy - p[84])) +
             p[87] * swc[4] * std::cos(2.0 * kDayRate * (doy - p[88]))) *
            ((p[64] * plg[1][2] + p[65] * plg[1][4] + p[66] * plg[1][6] + p[74] * plg[1][1] +
              p[75] * plg[1][3] + p[76] * plg[1][5]) *
                 std::cos(lon) +
             (p[90] * plg[1][2] + p[91] * plg[1][4] + p[92] * plg[1][6] + p[77] * plg[1][1] +
              p[78] * plg[1][3] + p[79] * plg[1][5]) *
                 std::sin(lon));
  }
  double g = 0.0;
  for (int i = 0; i < 14; ++i) g += std::fabs(sw[static_cast<std::size_t>(i) + 1]) * t[i];
  return g;
}

}  // namespace kessler::nrlmsise00
