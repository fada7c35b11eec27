#include "core/assessment/cdm_conjunction.hpp"

#include <charconv>
#include <cmath>
#include <limits>
#include <numbers>

#include <Eigen/Cholesky>

namespace kessler::assessment {

namespace {

constexpr double kEarthRotationRad_s = 7.292115e-5;  // IERS

bool parse_number(const CdmField& f, double& out, std::vector<CdmError>& errors) {
  const char* begin = f.value.data();
  const char* end = begin + f.value.size();
  if (begin != end && *begin == '+') ++begin;
  const auto [ptr, ec] = std::from_chars(begin, end, out);
  if (ec != std::errc() || ptr != end || !std::isfinite(out)) {
    errors.push_back(cdm_error(f.line, f.keyword, "not a number: '" + f.value + "'"));
    return false;
  }
  return true;
}

bool number_of(const std::vector<CdmField>& section, std::string_view keyword, double& out,
               std::vector<CdmError>& errors) {
  const CdmField* f = Cdm::find(section, keyword);
  return f && parse_number(*f, out, errors);
}

// The first number after '=' in a comment "<label> = value ...", or the keyword's value.
std::optional<double> labelled_number(const std::vector<CdmField>& section, std::string_view label) {
  for (const CdmField& f : section) {
    if (f.keyword == label) {
      double r = 0.0;
      std::vector<CdmError> ignored;
      if (parse_number(f, r, ignored)) return r;
    }
    if (f.keyword != "COMMENT" || !std::string_view(f.value).starts_with(label)) continue;
    const auto equals = f.value.find('=');
    if (equals == std::string::npos) continue;
    try {
      return std::stod(f.value.substr(equals + 1));
    } catch (...) {
      continue;
    }
  }
  return std::nullopt;
}

bool is_earth_fixed(std::string_view frame) {
  return frame.starts_with("ITRF") || frame == "ITRF";
}

void read_object(const std::vector<CdmField>& section, CdmObjectState& out, std::vector<CdmError>& errors) {
  if (const CdmField* f = Cdm::find(section, "OBJECT_DESIGNATOR")) out.designator = f->value;
  if (const CdmField* f = Cdm::find(section, "OBJECT_NAME")) out.name = f->value;
  if (const CdmField* f = Cdm::find(section, "REF_FRAME")) out.ref_frame = f->value;
  std::array<double, 6> state{};
  const std::array<std::string_view, 6> state_keys = {"X", "Y", "Z", "X_DOT", "Y_DOT", "Z_DOT"};
  bool state_ok = true;
  for (std::size_t i = 0; i < 6; ++i)
    state_ok = number_of(section, state_keys[i], state[i], errors) && state_ok;
  out.state.r_m = Eigen::Vector3d(state[0], state[1], state[2]) * 1000.0;
  out.state.v_m_s = Eigen::Vector3d(state[3], state[4], state[5]) * 1000.0;
  if (is_earth_fixed(out.ref_frame))
    out.state.v_m_s += Eigen::Vector3d(0.0, 0.0, kEarthRotationRad_s).cross(out.state.r_m);
  number_of(section, "AREA_PC", out.area_pc_m2, errors);
  const std::array<std::string_view, 6> cov_keys = {"CR_R", "CT_R", "CT_T", "CN_R", "CN_T", "CN_N"};
  std::array<double, 6> c{};
  bool cov_ok = state_ok;
  for (std::size_t i = 0; i < 6; ++i) cov_ok = number_of(section, cov_keys[i], c[i], errors) && cov_ok;
  const CdmField* first = Cdm::find(section, "CR_R");
  out.covariance_line = first ? first->line : 0;
  if (!cov_ok) return;
  Eigen::Matrix3d m;
  m << c[0], c[1], c[3], c[1], c[2], c[4], c[3], c[4], c[5];
  if (Eigen::LLT<Eigen::Matrix3d>(m).info() != Eigen::Success) {
    errors.push_back(
        cdm_error(out.covariance_line, "CR_R",
                  "the position covariance (CR_R..CN_N) is not positive definite: no Pc from it"));
    return;
  }
  out.state.rtn_covariance_m2 = m;
}

}  // namespace

bool read_conjunction(const Cdm& cdm, CdmConjunction& out, std::vector<CdmError>& errors) {
  const std::size_t before = errors.size();
  check_mandatory(cdm, errors);
  check_units(cdm, errors);
  if (const CdmField* f = Cdm::find(cdm.relative, "TCA")) out.tca = f->value;
  number_of(cdm.relative, "MISS_DISTANCE", out.miss_distance_m, errors);
  double pc = 0.0;
  if (Cdm::find(cdm.relative, "COLLISION_PROBABILITY") &&
      number_of(cdm.relative, "COLLISION_PROBABILITY", pc, errors))
    out.cdm_pc = pc;
  if (const CdmField* f = Cdm::find(cdm.relative, "COLLISION_PROBABILITY_METHOD"))
    out.cdm_pc_method = f->value;
  for (std::size_t i = 0; i < 2; ++i) read_object(cdm.objects[i], out.objects[i], errors);
  // The combined radius in the relative data, else each object's own (CSpOC's exclusion radius) summed.
  // (A comment just before OBJECT1 reads as the object's: look there for the HBR too.)
  out.hard_body_radius_m = labelled_number(cdm.relative, "HBR");
  if (!out.hard_body_radius_m) out.hard_body_radius_m = labelled_number(cdm.objects[0], "HBR");
  const std::optional<double> r1 = labelled_number(cdm.objects[0], "Exclusion Volume Radius");
  const std::optional<double> r2 = labelled_number(cdm.objects[1], "Exclusion Volume Radius");
  if (!out.hard_body_radius_m && r1 && r2) out.hard_body_radius_m = *r1 + *r2;
  return errors.size() == before;
}

double choose_hard_body_radius(const CdmConjunction& c, std::optional<double> given_m) {
  if (given_m) return *given_m;
  if (c.hard_body_radius_m) return *c.hard_body_radius_m;
  if (c.objects[0].area_pc_m2 > 0.0 && c.objects[1].area_pc_m2 > 0.0)
    return std::sqrt(c.objects[0].area_pc_m2 / std::numbers::pi) +
           std::sqrt(c.objects[1].area_pc_m2 / std::numbers::pi);
  return std::numeric_limits<double>::quiet_NaN();
}

Assessment assess_cdm(const CdmConjunction& c, double hbr_m, PcMethod method) {
  return assess(c.objects[0].state, c.objects[1].state, hbr_m, method, CovarianceSource::kCdm);
}

}  // namespace kessler::assessment
