// What the figures are drawn from and what they are: each figure is a function from a FigureSubject
// (runs with their stats, or an ensemble with its members) to a complete Vega-Lite v5 spec with its
// data inline, or null when it does not apply. The registry (figures.hpp) lists them.
#pragma once

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

#include "kessler/v1/service.pb.h"
#include "server/store.hpp"

namespace kessler::server::figures {

struct Figure {
  std::string id;  // stable, e.g. "conjunctions-over-time"
  std::string title;
  nlohmann::json spec;  // Vega-Lite v5
  bool partial = false;
};

// One run as the figures read it.
struct RunData {
  std::string label;         // "run 7"
  v1::Run run;               // without its scenario
  v1::RunStats stats;        // at kappa 1, 2, 5, 10 in the default bins
  v1::RunStats kappa_sweep;  // totals at kSweepKappas
  EventTimes events;
};

// The kappa thresholds of the conjunctions-against-kappa figure (the paper's Fig. 4 right).
inline const std::vector<double> kSweepKappas = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10};

struct FigureSubject {
  std::vector<RunData> runs;  // the run first, then those compared with it; empty for an ensemble
  std::optional<v1::EnsembleReport> ensemble;  // with its series and members
  std::vector<v1::Run> ensemble_members;       // the members' runs (summaries, without scenarios)
  bool partial = false;                        // some run (or member) has not ended
};

// Figure functions (one file each under server/figures/).
nlohmann::json conjunctions_over_time(const FigureSubject& subject);  // conjunctions_by_kappa.cpp
nlohmann::json conjunctions_vs_kappa(const FigureSubject& subject);   // conjunctions_by_kappa.cpp
nlohmann::json runtime_breakdown(const FigureSubject& subject);       // runtime_breakdown.cpp
nlohmann::json objects_by_type(const FigureSubject& subject);         // objects_by_type.cpp

// Shared by the figure functions (spec_helpers.cpp).
struct TimeAxis {
  double seconds_per_unit;
  std::string title;  // "simulated time [days]"
};
// Days, or years for runs longer than two years.
TimeAxis time_axis_for(double longest_run_s);
// The simulated length of a run [s] from its stats bins.
double run_length_s(const v1::RunStats& stats);
// How far the run got [s]: its length when ended, else its latest progress.
double run_reached_s(const RunData& data);
// A spec's common head: schema, title, size, and the look shared by every figure.
nlohmann::json base_spec(const std::string& title, const std::string& subtitle = "");

}  // namespace kessler::server::figures
