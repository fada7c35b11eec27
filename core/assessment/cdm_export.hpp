// A detected conjunction as a CDM: header, relative metadata (TCA, miss distance, relative speed, the
// relative position and velocity of object 2 in object 1's RTN frame, Pc and its method), and per object
// its metadata, TEME state at TCA and the covariance used (the model's position covariance; velocity
// terms not modelled, written as 0 with a comment saying so).
#pragma once

#include <cstdint>
#include <string>

#include "core/assessment/assess_encounter.hpp"
#include "core/assessment/cdm.hpp"
#include "core/conjunctions/encounter.hpp"
#include "core/time/epoch.hpp"

namespace kessler::assessment {

struct CdmObjectInfo {
  std::uint64_t id = 0;   // the run's object id (the catalog number for catalog runs)
  std::string name;       // empty: "OBJECT <id>"
  ObjectContext context;  // for the model's covariance
};

struct CdmExportOptions {
  std::string originator = "KESSLER";
  std::string message_id;   // e.g. "RUN12_SEQ345"
  UtcEpoch creation_date;   // written as CREATION_DATE
  UtcEpoch scenario_epoch;  // tca_s counts from here
};

Cdm cdm_from_encounter(const Encounter& encounter, const CdmObjectInfo& object1, const CdmObjectInfo& object2,
                       const CdmExportOptions& options);

}  // namespace kessler::assessment
