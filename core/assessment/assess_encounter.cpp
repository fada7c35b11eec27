#include "core/assessment/assess_encounter.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/assessment/covariance_model.hpp"
#include "core/assessment/encounter_plane.hpp"
#include "core/assessment/max_pc.hpp"
#include "core/assessment/pc_chan.hpp"
#include "core/assessment/pc_foster.hpp"

namespace kessler::assessment {

std::string_view method_name(PcMethod method) {
  return method == PcMethod::kFoster ? "foster" : "chan";
}

std::string_view source_name(CovarianceSource source) {
  switch (source) {
    case CovarianceSource::kModel:
      return "model";
    case CovarianceSource::kCdm:
      return "cdm";
    case CovarianceSource::kNone:
      break;
  }
  return "none";
}

namespace {

constexpr double kChanTolerance = 1e-3;

Eigen::Matrix3d inertial_covariance(const ObjectAtTca& o, const Eigen::Matrix3d& rtn) {
  const Eigen::Matrix3d m = rtn_to_inertial(o.r_m, o.v_m_s);
  return m * rtn * m.transpose();
}

// Two-body period from the state (vis-viva); infinite for an escape orbit.
double orbital_period_s(const ObjectAtTca& o) {
  constexpr double kMu_m3_s2 = 3.986004418e14;
  const double inverse_a = 2.0 / o.r_m.norm() - o.v_m_s.squaredNorm() / kMu_m3_s2;
  if (!(inverse_a > 0.0)) return std::numeric_limits<double>::infinity();
  return 2.0 * std::numbers::pi * std::sqrt(1.0 / (inverse_a * inverse_a * inverse_a) / kMu_m3_s2);
}

}  // namespace

void fill_max_pc(const ObjectAtTca& o1, const ObjectAtTca& o2, double hbr_m, Assessment& out) {
  const Eigen::Matrix3d shape = rtn_covariance(kSocratesShape);
  const Eigen::Matrix3d combined = inertial_covariance(o1, shape) + inertial_covariance(o2, shape);
  EncounterGeometry g;
  if (!project_to_encounter_plane(o2.r_m - o1.r_m, o2.v_m_s - o1.v_m_s, combined, g)) {
    out.pc_max = std::numeric_limits<double>::quiet_NaN();
    out.pc_max_sigma_m = std::numeric_limits<double>::quiet_NaN();
    return;
  }
  const MaxPc m = max_pc(g, hbr_m);
  out.pc_max = m.pc_max;
  out.pc_max_sigma_m = m.scale * kSocratesShape.radial_m;
}

Assessment assess(const ObjectAtTca& o1, const ObjectAtTca& o2, double hbr_m, PcMethod method,
                  CovarianceSource source) {
  Assessment out;
  out.method = method;
  out.covariance_source = source;
  out.pc = std::numeric_limits<double>::quiet_NaN();
  fill_max_pc(o1, o2, hbr_m, out);
  if (!o1.rtn_covariance_m2 || !o2.rtn_covariance_m2 || !(hbr_m > 0.0)) return out;
  const Eigen::Matrix3d combined =
      inertial_covariance(o1, *o1.rtn_covariance_m2) + inertial_covariance(o2, *o2.rtn_covariance_m2);
  const Eigen::Vector3d dv = o2.v_m_s - o1.v_m_s;
  out.encounter_duration_s = encounter_duration_s(dv, combined);
  const double period_s = std::min(orbital_period_s(o1), orbital_period_s(o2));
  out.short_encounter = out.encounter_duration_s <= kShortEncounterShare * period_s;
  EncounterGeometry g;
  if (!project_to_encounter_plane(o2.r_m - o1.r_m, dv, combined, g)) return out;
  // Chan's series where its equal-area approximation holds to 1e-3, else Foster's integral.
  if (method == PcMethod::kChan && chan_relative_error_estimate(g, hbr_m) > kChanTolerance)
    method = PcMethod::kFoster;
  out.method = method;
  out.pc = method == PcMethod::kFoster ? pc_foster(g, hbr_m) : pc_chan(g, hbr_m);
  out.pc_computed = true;
  return out;
}

double hard_body_radius_m(const Encounter& e) {
  return e.kappa > 0.0 ? e.miss_distance_m / e.kappa : std::numeric_limits<double>::quiet_NaN();
}

Assessment assess_encounter(const Encounter& e, const ObjectContext& c1, const ObjectContext& c2,
                            PcMethod method) {
  const double age_days = e.tca_s / 86400.0;
  ObjectAtTca o1{e.r1_m, e.v1_m_s,
                 rtn_covariance(modelled_sigmas(c1.type, c1.element_set_age_at_epoch_days + age_days))};
  ObjectAtTca o2{e.r2_m, e.v2_m_s,
                 rtn_covariance(modelled_sigmas(c2.type, c2.element_set_age_at_epoch_days + age_days))};
  return assess(o1, o2, hard_body_radius_m(e), method, CovarianceSource::kModel);
}

}  // namespace kessler::assessment
