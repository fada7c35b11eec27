// What an assessment needs from a CDM, as numbers: the two objects' states and RTN position
// covariances, the hard-body radius where the message gives one, and the message's own Pc.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "core/assessment/assess_encounter.hpp"
#include "core/assessment/cdm.hpp"

namespace kessler::assessment {

struct CdmObjectState {
  std::string designator, name, ref_frame;
  ObjectAtTca state;        // metres and m/s, in the message's frame (Earth-fixed: with the Earth's rotation
                            // added to the velocity, so that the RTN frames are the inertial ones)
  double area_pc_m2 = 0.0;  // AREA_PC, 0 when absent
  std::size_t covariance_line = 0;
};

struct CdmConjunction {
  std::string tca;
  double miss_distance_m = 0.0;
  std::optional<double> cdm_pc;  // COLLISION_PROBABILITY
  std::string cdm_pc_method;
  // The relative data's HBR (keyword or comment "HBR = R"), else the sum of the objects' own radii
  // (comments "Exclusion Volume Radius = R [m]", as CSpOC writes them)
  std::optional<double> hard_body_radius_m;
  std::array<CdmObjectState, 2> objects;
};

// Reads the numbers (mandatory keywords, units and numeric values checked; every problem into errors,
// with line and keyword). A position covariance that is not positive definite is reported and left
// out (the object's rtn_covariance_m2 empty), so no Pc is computed from it. True when no error.
bool read_conjunction(const Cdm& cdm, CdmConjunction& out, std::vector<CdmError>& errors);

// The hard-body radius to use: the given one, else the CDM's, else from the objects' AREA_PC
// (sqrt(A / pi) each, summed); NaN when none of these exists.
double choose_hard_body_radius(const CdmConjunction& conjunction, std::optional<double> given_m);

// Pc from the message's states and covariances.
Assessment assess_cdm(const CdmConjunction& conjunction, double hard_body_radius_m,
                      PcMethod method = PcMethod::kFoster);

}  // namespace kessler::assessment
