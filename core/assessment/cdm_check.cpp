// The standard's mandatory keywords and units (CCSDS 508.0-B-1, tables 3-2 to 3-5).
#include <array>

#include "core/assessment/cdm.hpp"

namespace kessler::assessment {

namespace {

constexpr std::array<std::string_view, 4> kHeaderMandatory = {"CCSDS_CDM_VERS", "CREATION_DATE", "ORIGINATOR",
                                                              "MESSAGE_ID"};
constexpr std::array<std::string_view, 2> kRelativeMandatory = {"TCA", "MISS_DISTANCE"};
constexpr std::array<std::string_view, 36> kObjectMandatory = {"OBJECT",
                                                               "OBJECT_DESIGNATOR",
                                                               "CATALOG_NAME",
                                                               "OBJECT_NAME",
                                                               "INTERNATIONAL_DESIGNATOR",
                                                               "EPHEMERIS_NAME",
                                                               "COVARIANCE_METHOD",
                                                               "MANEUVERABLE",
                                                               "REF_FRAME",
                                                               "X",
                                                               "Y",
                                                               "Z",
                                                               "X_DOT",
                                                               "Y_DOT",
                                                               "Z_DOT",
                                                               "CR_R",
                                                               "CT_R",
                                                               "CT_T",
                                                               "CN_R",
                                                               "CN_T",
                                                               "CN_N",
                                                               "CRDOT_R",
                                                               "CRDOT_T",
                                                               "CRDOT_N",
                                                               "CRDOT_RDOT",
                                                               "CTDOT_R",
                                                               "CTDOT_T",
                                                               "CTDOT_N",
                                                               "CTDOT_RDOT",
                                                               "CTDOT_TDOT",
                                                               "CNDOT_R",
                                                               "CNDOT_T",
                                                               "CNDOT_N",
                                                               "CNDOT_RDOT",
                                                               "CNDOT_TDOT",
                                                               "CNDOT_NDOT"};

template <std::size_t N>
void require(const std::vector<CdmField>& section, const std::array<std::string_view, N>& keywords,
             std::size_t section_line, std::string_view where, std::vector<CdmError>& errors) {
  for (const std::string_view k : keywords)
    if (!Cdm::find(section, k))
      errors.push_back(
          cdm_error(section_line, k, std::string("mandatory keyword missing from ") + std::string(where)));
}

std::size_t first_line(const std::vector<CdmField>& section) {
  return section.empty() ? 0 : section.front().line;
}

// The unit a keyword must carry when it carries one (empty: none checked).
std::string_view expected_unit(std::string_view k) {
  if (k == "MISS_DISTANCE" || k.starts_with("RELATIVE_POSITION_")) return "m";
  if (k == "RELATIVE_SPEED" || k.starts_with("RELATIVE_VELOCITY_")) return "m/s";
  if (k == "X" || k == "Y" || k == "Z") return "km";
  if (k == "X_DOT" || k == "Y_DOT" || k == "Z_DOT") return "km/s";
  // The position-velocity covariance: m**2 times 1/s per velocity index.
  static constexpr std::array<std::string_view, 3> kByVelocityCount = {"m**2", "m**2/s", "m**2/s**2"};
  const auto underscore = k.find('_');
  if (k.size() > 2 && k[0] == 'C' && underscore != std::string_view::npos) {
    const std::string_view a = k.substr(1, underscore - 1);
    const std::string_view b = k.substr(underscore + 1);
    auto axis = [](std::string_view s) {
      return s == "R" || s == "T" || s == "N" ? 0 : s == "RDOT" || s == "TDOT" || s == "NDOT" ? 1 : -1;
    };
    const int ia = axis(a);
    const int ib = axis(b);
    if (ia >= 0 && ib >= 0)
      return kByVelocityCount[static_cast<std::size_t>(ia) + static_cast<std::size_t>(ib)];
  }
  return {};
}

void check_section_units(const std::vector<CdmField>& section, std::vector<CdmError>& errors) {
  for (const CdmField& f : section) {
    const std::string_view unit = expected_unit(f.keyword);
    if (!unit.empty() && !f.unit.empty() && f.unit != unit)
      errors.push_back(cdm_error(f.line, f.keyword,
                                 "unit [" + f.unit + "] where [" + std::string(unit) + "] is required"));
  }
}

}  // namespace

void check_mandatory(const Cdm& cdm, std::vector<CdmError>& errors) {
  require(cdm.header, kHeaderMandatory, first_line(cdm.header), "the header", errors);
  require(cdm.relative, kRelativeMandatory, first_line(cdm.relative), "the relative metadata", errors);
  require(cdm.objects[0], kObjectMandatory, first_line(cdm.objects[0]), "OBJECT1", errors);
  require(cdm.objects[1], kObjectMandatory, first_line(cdm.objects[1]), "OBJECT2", errors);
}

void check_units(const Cdm& cdm, std::vector<CdmError>& errors) {
  check_section_units(cdm.relative, errors);
  check_section_units(cdm.objects[0], errors);
  check_section_units(cdm.objects[1], errors);
}

}  // namespace kessler::assessment
