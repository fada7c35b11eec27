#include "core/assessment/covariance_model.hpp"

#include <algorithm>
#include <array>

namespace kessler::assessment {

namespace {

struct TypeRow {
  RtnSigmas at_epoch;              // metres
  double transverse_growth_m_day;  // along-track growth, metres per day of element-set age
  double radial_growth_m_day;      // radial and cross-track growth, metres per day
};

// Rows by ObjectType: unknown, payload, rocket body, debris.
constexpr std::array<TypeRow, 4> kRows = {{
    {{250.0, 1200.0, 250.0}, 1500.0, 100.0},  // unknown: as debris
    {{150.0, 600.0, 150.0}, 800.0, 50.0},     // payload
    {{200.0, 900.0, 200.0}, 1200.0, 80.0},    // rocket body
    {{250.0, 1200.0, 250.0}, 1500.0, 100.0},  // debris
}};

}  // namespace

RtnSigmas modelled_sigmas(ObjectType type, double age_days) {
  const auto index = static_cast<std::size_t>(type);
  const TypeRow& row = kRows[index < kRows.size() ? index : 0];
  const double age = std::max(0.0, age_days);
  return {row.at_epoch.radial_m + row.radial_growth_m_day * age,
          row.at_epoch.transverse_m + row.transverse_growth_m_day * age,
          row.at_epoch.normal_m + row.radial_growth_m_day * age};
}

Eigen::Matrix3d rtn_covariance(const RtnSigmas& s) {
  return Eigen::Vector3d(s.radial_m * s.radial_m, s.transverse_m * s.transverse_m, s.normal_m * s.normal_m)
      .asDiagonal();
}

ObjectType object_type_from_name(std::string_view name) {
  if (name.empty()) return ObjectType::kUnknown;
  if (name.find(" DEB") != std::string_view::npos || name.starts_with("FRAGMENT")) return ObjectType::kDebris;
  if (name.find(" R/B") != std::string_view::npos) return ObjectType::kRocketBody;
  return ObjectType::kPayload;
}

}  // namespace kessler::assessment
