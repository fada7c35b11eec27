// The deep-space (SDP4) parts of SGP4 for orbits with periods of 225 minutes or more: lunar and solar
// secular and long-periodic terms, and the 12-hour and 24-hour geopotential resonances (Hujsak 1979, as
// corrected by Vallado et al. 2006). Internal to core/sgp4.
#pragma once

#include "core/sgp4/sgp4.hpp"

namespace kessler::sgp4 {

// Quantities shared by the lunar-solar initialisation steps (the theory's "dscom" outputs).
struct DeepSpaceCommon {
  double snodm, cnodm, sinim, cosim, sinomm, cosomm, day, em, emsq, gam, rtemsq, nm;
  double s1, s2, s3, s4, s5, s6, s7, ss1, ss2, ss3, ss4, ss5, ss6, ss7;
  double sz1, sz2, sz3, sz11, sz12, sz13, sz21, sz22, sz23, sz31, sz32, sz33;
  double z1, z2, z3, z11, z12, z13, z21, z22, z23, z31, z32, z33;
};

// Lunar and solar perturbation coefficients at epoch; fills the record's e3..zmos fields.
void deep_space_common(double epoch_days, double ep, double argpp, double tc, double inclp, double nodep,
                       double np, Sgp4Record& record, DeepSpaceCommon& out);

// Long-periodic lunar-solar terms at `t_min` added to the elements (at_epoch: the values at epoch that
// the record's p*o fields will hold).
void deep_space_periodics(const Sgp4Record& record, double t_min, bool at_epoch, double& ep, double& inclp,
                          double& nodep, double& argpp, double& mp);

// Secular rates and resonance coefficients; fills the record's d*, del*, xfact, xlamo, irez.
struct DeepSpaceMeanState {
  double em, argpm, inclm, mm, nm, nodem;
};
void deep_space_initialise(const DeepSpaceCommon& common, double t_min, double xpidot, double eccsq,
                           Sgp4Record& record, DeepSpaceMeanState& state);

// Secular lunar-solar effects and resonance integration from epoch to t_min (restarted from epoch on
// every call, which gives the same numbers as the reference's cached integrator: same steps, same sums).
void deep_space_secular(const Sgp4Record& record, double t_min, DeepSpaceMeanState& state);

}  // namespace kessler::sgp4
