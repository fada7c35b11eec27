// Conjunctions with their collision probability (core/assessment), computed when they are read: the
// listing's pc fields, its pc filter and sorts, and a conjunction's CDM.
//
// Why at query time rather than stored: Pc depends on a covariance model that is a model (and will be
// revised) while the events and their digests must not change; computing it costs about a
// microsecond per event, so even a sorted listing of a week of leo-19647 (218,000 events) is dominated
// by reading the rows, and the store keeps its schema.
#pragma once

#include <cstdint>
#include <string>

#include "core/time/epoch.hpp"
#include "kessler/v1/service.pb.h"
#include "server/store.hpp"

namespace kessler::server {

// Sets pc, pc_method, covariance_source, pc_max, pc_max_sigma_m and short_encounter from the
// encounter's states at TCA, its names (object types) and kappa (hard-body radius).
void fill_assessment(v1::Encounter& encounter);

// The listing with pc filled; with pc_min or a sort, every match is read, assessed, filtered and sorted
// before paging. Throws std::invalid_argument("field: reason") for a bad sort, pc_min or page token.
v1::ListConjunctionsResponse assessed_conjunctions(Store& store, const v1::ListConjunctionsRequest& request);

// The conjunction as a CDM; start_epoch: the scenario's epoch (tca_s counts from it).
// Throws std::invalid_argument("format: ...") for a format other than kvn / xml.
v1::ConjunctionCdm conjunction_cdm(const v1::Encounter& encounter, std::int64_t run_id,
                                   const UtcEpoch& start_epoch, const std::string& format);

}  // namespace kessler::server
