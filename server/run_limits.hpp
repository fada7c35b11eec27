// Per-run limits a submission is held to, from the scenario alone (before anything runs), and the cap on
// a running run's stored events.
//
// A scenario that could never finish in reasonable time or would fill the disk is refused at SubmitRun
// (INVALID_ARGUMENT naming the field and the limit) instead of occupying a worker for a year. The
// estimates are upper bounds from the scenario's own numbers: objects (synthetic count, a bundled
// dataset's size, an ingested catalog's kept objects, capped by population.max_objects), steps
// (duration / dt_s), object-steps, and the wall time those object-steps cost on one core.
#pragma once

#include <atomic>
#include <cstdint>
#include <optional>
#include <string>

#include "core/scenario/run_builder.hpp"
#include "core/simulation/events.hpp"
#include "kessler/v1/scenario.pb.h"

namespace kessler::server {

struct RunLimits {
  std::uint64_t max_objects = 2'000'000;
  std::uint64_t max_steps = 200'000'000;  // the paper's 20 years at 10 s: 63 million
  double max_object_steps = 2e13;         // the paper's 20 years of leo-19647: 1.2e12
  double max_wall_hours = 720.0;          // estimated on one core
  double max_screening_km = 100.0;        // screening distance; beyond it every step floods
  std::uint64_t max_events = 50'000'000;  // events stored per run; a run that emits more fails
};

// One core's cost of an object-step with conjunction detection (kessler-bench run on leo-19647: 185 ns;
// a little above, so the estimate bounds the real time).
inline constexpr double kEstimatedSecondsPerObjectStep = 200e-9;

// What the limits are checked against, from a scenario that passed validate_scenario.
struct RunEstimate {
  std::uint64_t objects = 0;
  std::int64_t steps = 0;
  double object_steps = 0.0;
  double wall_hours = 0.0;  // on one core
};

// `ingested_objects`: the objects an inline catalog or state table kept at submission (nullopt for
// other sources, whose size the scenario or the dataset gives).
RunEstimate estimate_run(const v1::Scenario& scenario, std::optional<std::uint64_t> ingested_objects);

// The first limit the scenario exceeds, with the field at fault.
std::optional<FieldError> check_run_limits(const v1::Scenario& scenario, const RunEstimate& estimate,
                                           const RunLimits& limits);

// kesslerd's flags for the limits, for its --help.
extern const char* const kRunLimitsUsage;

// When `flag` is one of the limits' flags: sets it from `value` and returns true; `error` is set when
// the value is not valid (a positive number).
bool parse_run_limit_flag(const std::string& flag, const std::string& value, RunLimits& limits,
                          std::string& error);

// Passes events on to `inner` until a run has emitted more than `max_events`; then it asks the run to
// stop (`control.cancel`) and drops what follows (checkpoints too: the run is failed, not resumed).
class EventLimitSink final : public EventSink {
 public:
  EventLimitSink(EventSink& inner, RunControl& control, std::uint64_t max_events)
      : inner_(inner), control_(control), max_events_(max_events) {}
  void on_encounter(std::uint64_t seq, const Encounter& e) override {
    if (admit(seq)) inner_.on_encounter(seq, e);
  }
  void on_burn_up(std::uint64_t seq, const BurnUp& b) override {
    if (admit(seq)) inner_.on_burn_up(seq, b);
  }
  void on_progress(std::uint64_t seq, const Progress& p) override {
    if (admit(seq)) inner_.on_progress(seq, p);
  }
  void on_breakup(std::uint64_t seq, const BreakupReport& b) override {
    if (admit(seq)) inner_.on_breakup(seq, b);
  }
  void on_lifecycle(std::uint64_t seq, const LifecycleReport& l) override {
    if (admit(seq)) inner_.on_lifecycle(seq, l);
  }
  void on_snapshot(const std::shared_ptr<const PopulationSnapshot>& snapshot) override {
    if (!exceeded()) inner_.on_snapshot(snapshot);
  }
  void on_checkpoint(std::uint64_t last_seq, std::int64_t step, const std::string& bytes) override {
    if (!exceeded()) inner_.on_checkpoint(last_seq, step, bytes);
  }
  void on_finished(const RunSummary& s) override { inner_.on_finished(s); }
  void on_failed(const std::string& reason) override { inner_.on_failed(reason); }

  bool exceeded() const { return exceeded_.load(); }
  std::string failure() const;

 private:
  bool admit(std::uint64_t seq) {
    if (seq <= max_events_ && !exceeded()) return true;
    exceeded_ = true;
    control_.cancel = true;
    return false;
  }
  EventSink& inner_;
  RunControl& control_;
  std::uint64_t max_events_;
  std::atomic<bool> exceeded_{false};
};

}  // namespace kessler::server
