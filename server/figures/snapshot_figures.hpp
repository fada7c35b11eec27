// The snapshot- and conjunction-based figures of a run, each a complete Vega-Lite v5 specification
// (data inline, axis titles with units), or a null json when the figure does not apply to the run (no
// snapshot, no conjunction, no breakup). Each takes what the service layer reads for a run
// (RunManager::population_snapshot, conjunctions, fragments); run_figures.cpp gathers them for a run id.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/simulation/snapshots.hpp"
#include "kessler/v1/service.pb.h"

namespace kessler::server {

class RunManager;

// 1. The population's distributions of mass, radius and semi-major axis (as altitude) by status (the
// LADDS paper's Fig. 3): logarithmic bins for mass and radius, 50 km bins for the altitude.
nlohmann::json population_distributions_figure(const PopulationSnapshot& snapshot);

// 3. Sizes of the two objects of each conjunction (larger against smaller radius, a 2-D density), and
// the radius distribution of the objects in conjunctions against the population's, as fractions (the
// paper's Fig. 5). Radii come from `population` by id; objects it lacks are left out (counted in the
// description).
nlohmann::json conjunction_sizes_figure(const std::vector<v1::Encounter>& conjunctions,
                                        const PopulationSnapshot& population);

// 4. Semi-major axis (as altitude) and inclination of the objects in conjunctions, from their states at
// closest approach, against the population's (the paper's Fig. 6), as fractions.
nlohmann::json conjunction_orbits_figure(const std::vector<v1::Encounter>& conjunctions,
                                         const PopulationSnapshot& population);

// 7. Spatial density [objects / km^3] against altitude at the start and at the end, and its change:
// each bound orbit spread over 20 km shells by the time it spends in each (sampled at 64 equal steps
// of mean anomaly), so density times shell volume summed over shells is the number of bound objects.
nlohmann::json spatial_density_figure(const PopulationSnapshot& start, const PopulationSnapshot& end);

// 8. Gabbard diagrams: apogee and perigee altitude against period of each breakup's fragments, one
// panel per snapshot given (the chosen epochs), coloured by breakup. At most 20,000 points per panel
// (an even subsample beyond, said in the description).
nlohmann::json gabbard_figure(const std::vector<v1::Fragment>& fragments,
                              const std::vector<PopulationSnapshot>& snapshots);

// Every figure that applies to the run, by name ("population_distributions", "conjunction_sizes",
// "conjunction_orbits", "spatial_density", "gabbard"), read through the run manager. The Gabbard
// diagram's epochs: up to 4 snapshots after the first breakup, evenly spread. NOT_FOUND (ServiceError)
// for an unknown run.
nlohmann::json run_figures(RunManager& manager, std::int64_t run_id);

}  // namespace kessler::server
