#include "core/assessment/cdm_export.hpp"

#include <array>
#include <cstdio>

#include "core/assessment/covariance_model.hpp"
#include "core/assessment/encounter_plane.hpp"

namespace kessler::assessment {

namespace {

std::string format(const char* pattern, double value) {
  std::array<char, 64> buffer{};
  std::snprintf(buffer.data(), buffer.size(), pattern, value);
  return buffer.data();
}

void add(std::vector<CdmField>& s, std::string keyword, std::string value, std::string unit = {}) {
  s.push_back({std::move(keyword), std::move(value), std::move(unit), 0});
}

void add_object(std::vector<CdmField>& s, const char* label, const CdmObjectInfo& info,
                const Eigen::Vector3d& r_m, const Eigen::Vector3d& v_m_s, const Eigen::Matrix3d& rtn_m2) {
  add(s, "OBJECT", label);
  add(s, "OBJECT_DESIGNATOR", std::to_string(info.id));
  add(s, "CATALOG_NAME", "SATCAT");
  add(s, "OBJECT_NAME", info.name.empty() ? "OBJECT " + std::to_string(info.id) : info.name);
  add(s, "INTERNATIONAL_DESIGNATOR", "UNKNOWN");
  add(s, "EPHEMERIS_NAME", "NONE");
  add(s, "COVARIANCE_METHOD", "DEFAULT");
  add(s, "MANEUVERABLE", "N/A");
  add(s, "REF_FRAME", "TEME");
  add(s, "COMMENT", "State at TCA from the Kessler run (TEME of the scenario epoch)");
  const std::array<const char*, 3> axes = {"X", "Y", "Z"};
  for (int i = 0; i < 3; ++i)
    add(s, axes[static_cast<std::size_t>(i)], format("%.9f", r_m[i] / 1000.0), "km");
  for (int i = 0; i < 3; ++i)
    add(s, std::string(axes[static_cast<std::size_t>(i)]) + "_DOT", format("%.12f", v_m_s[i] / 1000.0),
        "km/s");
  add(s, "COMMENT", "Position covariance from Kessler's covariance model; velocity terms not modelled (0)");
  add(s, "CR_R", format("%.10e", rtn_m2(0, 0)), "m**2");
  add(s, "CT_R", format("%.10e", rtn_m2(1, 0)), "m**2");
  add(s, "CT_T", format("%.10e", rtn_m2(1, 1)), "m**2");
  add(s, "CN_R", format("%.10e", rtn_m2(2, 0)), "m**2");
  add(s, "CN_T", format("%.10e", rtn_m2(2, 1)), "m**2");
  add(s, "CN_N", format("%.10e", rtn_m2(2, 2)), "m**2");
  for (const char* k : {"CRDOT_R", "CRDOT_T", "CRDOT_N"}) add(s, k, "0.0", "m**2/s");
  add(s, "CRDOT_RDOT", "0.0", "m**2/s**2");
  for (const char* k : {"CTDOT_R", "CTDOT_T", "CTDOT_N"}) add(s, k, "0.0", "m**2/s");
  for (const char* k : {"CTDOT_RDOT", "CTDOT_TDOT"}) add(s, k, "0.0", "m**2/s**2");
  for (const char* k : {"CNDOT_R", "CNDOT_T", "CNDOT_N"}) add(s, k, "0.0", "m**2/s");
  for (const char* k : {"CNDOT_RDOT", "CNDOT_TDOT", "CNDOT_NDOT"}) add(s, k, "0.0", "m**2/s**2");
}

}  // namespace

Cdm cdm_from_encounter(const Encounter& e, const CdmObjectInfo& o1, const CdmObjectInfo& o2,
                       const CdmExportOptions& options) {
  Cdm cdm;
  add(cdm.header, "CCSDS_CDM_VERS", "1.0");
  add(cdm.header, "CREATION_DATE", options.creation_date.to_iso8601(3).substr(0, 23));
  add(cdm.header, "ORIGINATOR", options.originator);
  add(cdm.header, "MESSAGE_ID", options.message_id);

  const Assessment a = assess_encounter(e, o1.context, o2.context, PcMethod::kChan);
  const Eigen::Matrix3d to_inertial = rtn_to_inertial(e.r1_m, e.v1_m_s);
  const Eigen::Vector3d dr = to_inertial.transpose() * (e.r2_m - e.r1_m);
  const Eigen::Vector3d dv = to_inertial.transpose() * (e.v2_m_s - e.v1_m_s);
  auto& rel = cdm.relative;
  // Comments open a section (a comment last in one would read as the next section's).
  add(rel, "COMMENT", "HBR = " + format("%.4f", hard_body_radius_m(e)) + " [m]");
  add(rel, "COMMENT",
      "Maximum Pc (SOCRATES shape 100/300/100 m) = " + format("%.6e", a.pc_max) + " at a radial sigma of " +
          format("%.1f", a.pc_max_sigma_m) + " [m]");
  add(rel, "TCA", options.scenario_epoch.plus_seconds(e.tca_s).to_iso8601(6).substr(0, 26));
  add(rel, "MISS_DISTANCE", format("%.3f", e.miss_distance_m), "m");
  add(rel, "RELATIVE_SPEED", format("%.3f", e.relative_speed_m_s), "m/s");
  const std::array<const char*, 3> rtn = {"R", "T", "N"};
  for (int i = 0; i < 3; ++i)
    add(rel, std::string("RELATIVE_POSITION_") + rtn[static_cast<std::size_t>(i)], format("%.3f", dr[i]),
        "m");
  for (int i = 0; i < 3; ++i)
    add(rel, std::string("RELATIVE_VELOCITY_") + rtn[static_cast<std::size_t>(i)], format("%.4f", dv[i]),
        "m/s");
  if (a.pc_computed) {
    add(rel, "COLLISION_PROBABILITY", format("%.6e", a.pc));
    add(rel, "COLLISION_PROBABILITY_METHOD", a.method == PcMethod::kFoster ? "FOSTER-1992" : "CHAN-1997");
  }
  const double age_days = e.tca_s / 86400.0;
  add_object(
      cdm.objects[0], "OBJECT1", o1, e.r1_m, e.v1_m_s,
      rtn_covariance(modelled_sigmas(o1.context.type, o1.context.element_set_age_at_epoch_days + age_days)));
  add_object(
      cdm.objects[1], "OBJECT2", o2, e.r2_m, e.v2_m_s,
      rtn_covariance(modelled_sigmas(o2.context.type, o2.context.element_set_age_at_epoch_days + age_days)));
  return cdm;
}

}  // namespace kessler::assessment
