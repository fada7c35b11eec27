// A conjunction's collision probability: its states at TCA, the objects' covariances (given, or the
// model's) and the hard-body radius, through the encounter plane to Pc (Chan's series by default,
// Foster's integral on request), with the SOCRATES-style maximum Pc beside it.
#pragma once

#include <optional>
#include <string_view>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/conjunctions/encounter.hpp"
#include "core/population/population.hpp"

namespace kessler::assessment {

enum class PcMethod : std::uint8_t { kChan = 0, kFoster = 1 };
enum class CovarianceSource : std::uint8_t { kNone = 0, kModel = 1, kCdm = 2 };

std::string_view method_name(PcMethod method);          // "chan", "foster"
std::string_view source_name(CovarianceSource source);  // "none", "model", "cdm"

// One object at TCA: state (any inertial frame shared by both objects) and, where known, its position
// covariance in its own RTN frame (m^2).
struct ObjectAtTca {
  Eigen::Vector3d r_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_m_s = Eigen::Vector3d::Zero();
  std::optional<Eigen::Matrix3d> rtn_covariance_m2;
};

struct Assessment {
  bool pc_computed = false;  // false: no covariance, a zero relative velocity or a covariance that is not
                             // positive definite in the encounter plane (pc is then NaN)
  double pc = 0.0;
  PcMethod method = PcMethod::kChan;
  CovarianceSource covariance_source = CovarianceSource::kNone;
  double pc_max = 0.0;                // the maximum over the scale of the SOCRATES shape
  double pc_max_sigma_m = 0.0;        // dilution sigma: each object's radial 1-sigma at that maximum
  double encounter_duration_s = 0.0;  // +-5 sigma of the combined covariance crossed at the relative speed
  // The 2-D short-encounter assumption holds: the encounter lasts at most kShortEncounterShare of the
  // shorter orbital period of the two (straight-line relative motion, a fixed covariance). Where it does
  // not, the 2-D Pc is still computed but is not to be trusted.
  bool short_encounter = true;
};

inline constexpr double kShortEncounterShare = 0.01;

// Pc from the two objects' covariances (both must be given), and the maximum Pc. PcMethod::kChan
// uses Chan's series where its error estimate is below 1e-3 and Foster's integral elsewhere
// (Assessment::method says which).
Assessment assess(const ObjectAtTca& object1, const ObjectAtTca& object2, double hard_body_radius_m,
                  PcMethod method, CovarianceSource source);

// The maximum Pc over the scale of the SOCRATES shape alone (pc_max and pc_max_sigma_m).
void fill_max_pc(const ObjectAtTca& object1, const ObjectAtTca& object2, double hard_body_radius_m,
                 Assessment& out);

// A detected encounter, the objects' covariances from the model (by type and element-set age: the
// ages at the scenario epoch plus the encounter's time).
struct ObjectContext {
  ObjectType type = ObjectType::kUnknown;
  double element_set_age_at_epoch_days = 0.0;
};
Assessment assess_encounter(const Encounter& encounter, const ObjectContext& object1,
                            const ObjectContext& object2, PcMethod method = PcMethod::kChan);

// r1 + r2 of an encounter, from its miss distance and kappa = miss / (r1 + r2); NaN when kappa is 0.
double hard_body_radius_m(const Encounter& encounter);

}  // namespace kessler::assessment
