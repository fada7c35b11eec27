// Where no covariance is given: a model of an object's position uncertainty (1-sigma radial,
// transverse and normal, metres) from its type and the age of its element set. It is a model, not an
// estimate: the magnitudes follow published assessments of two-line element set errors in LEO (Flohrer
// et al. 2008: at epoch a few hundred metres radially and cross-track, about a kilometre along track,
// the along-track error growing by roughly a kilometre a day), with debris and rocket bodies less well
// known than payloads. core/assessment/README.md gives the table.
#pragma once

#include <string_view>

#include <Eigen/Core>

#include "core/population/population.hpp"

namespace kessler::assessment {

struct RtnSigmas {
  double radial_m = 0.0;
  double transverse_m = 0.0;
  double normal_m = 0.0;
};

// The model's sigmas for an object of this type whose element set is age_days old (negative: 0).
RtnSigmas modelled_sigmas(ObjectType type, double age_days);

// SOCRATES's fixed shape for its maximum probability: radial 100 m, in-track 300 m, cross-track 100 m.
inline constexpr RtnSigmas kSocratesShape{100.0, 300.0, 100.0};

// Diagonal RTN covariance of these sigmas (m^2).
Eigen::Matrix3d rtn_covariance(const RtnSigmas& sigmas);

// The object's type as its catalog name tells it (SATCAT conventions: " DEB" debris, " R/B" rocket
// body, "FRAGMENT" a breakup's fragment); unknown without a name, payload otherwise.
ObjectType object_type_from_name(std::string_view name);

}  // namespace kessler::assessment
