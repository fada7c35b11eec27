// The main loop: integrate, burn-up, detection, events, progress, checkpoints; each phase timed.
#include "core/simulation/simulation.hpp"

#include <omp.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <thread>
#include <utility>

#include "core/conjunctions/closest_encounters.hpp"
#include "core/simulation/checkpoint.hpp"
#include "core/simulation/run_digests.hpp"
#include "core/simulation/sha256.hpp"
#include "core/simulation/steps_in_flight.hpp"

namespace kessler {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Progress every this many steps: the configured value, else about 200 per run.
std::int64_t progress_interval(const SimulationConfig& c, std::int64_t total) {
  if (c.progress_every_steps > 0) return c.progress_every_steps;
  return std::max<std::int64_t>(1, total / 200);
}

ObjectCounts count_by_type(const Population& p) {
  ObjectCounts c;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.id[i] >= kFirstFragmentId && p.id[i] < kFirstLaunchId) {
      ++c.fragments;
      continue;
    }
    switch (p.type[i]) {
      case ObjectType::kPayload:
        ++c.payload;
        break;
      case ObjectType::kRocketBody:
        ++c.rocket_body;
        break;
      case ObjectType::kDebris:
        ++c.debris;
        break;
      case ObjectType::kUnknown:
        ++c.unknown;
        break;
    }
  }
  return c;
}

}  // namespace

std::int64_t total_steps_of(const SimulationConfig& config) {
  if (!(config.dt_s > 0.0) || !(config.duration_s > 0.0)) return 0;
  // The tiny tolerance keeps 86400 / 10 from landing a hair under 8640 after rounding.
  return static_cast<std::int64_t>(std::floor(config.duration_s / config.dt_s * (1.0 + 1e-12)));
}

struct Simulation::State {
  SimulationConfig config;
  std::string key;
  SimulationParts parts;
  Population population;
  std::int64_t step = 0;
  std::int64_t total_steps = 0;
  std::uint64_t next_seq = 1;
  RunCounters counters;
  double wall_before_s = 0.0;  // wall time of earlier sessions (resumed runs)
  Sha256 events_hash;
  ClosestEncounterTable closest;
  std::int64_t last_checkpoint_step = -1;
  BreakupIds breakups;  // run-level: fragment ids and breakup numbers never repeat in a run
  TrafficState traffic;
  bool actives_adopted = false;  // the population's own actives joined the lifecycle (adopt_catalog_actives)

  CheckpointState snapshot(double wall_s) const {
    CheckpointState c;
    c.config_key = key;
    c.step = step;
    c.total_steps = total_steps;
    c.next_seq = next_seq;
    c.seed = config.seed;
    static_cast<RunCounters&>(c) = counters;
    c.wall_s = wall_s;
    c.events_digest_state = events_hash.save_state();
    c.closest_per_pair = closest.entries();
    c.population = population;
    c.breakups = breakups;
    c.traffic = traffic;
    return c;
  }
};

Simulation::Simulation(const SimulationConfig& config, Population population, SimulationParts parts)
    : state_(std::make_unique<State>()) {
  if (!parts.propagator) throw std::invalid_argument("simulation: no propagator");
  if (config.breakups.enabled && !parts.propagator->takes_new_objects())
    throw std::invalid_argument(
        "breakups.enabled: breakups need the numerical propagator (SGP4 cannot "
        "move fragments, which have no element sets)");
  state_->config = config;
  state_->key = config_key(config);
  state_->parts = std::move(parts);
  state_->population = std::move(population);
  state_->total_steps = total_steps_of(config);
  state_->counters.objects_initial = state_->population.size();
}

std::unique_ptr<Simulation> Simulation::resume(const SimulationConfig& config, const std::string& checkpoint,
                                               SimulationParts parts) {
  CheckpointState c = decode_checkpoint(checkpoint);
  if (c.config_key != config_key(config))
    throw std::runtime_error(
        "checkpoint: taken by a run with a different scenario (step, epoch, duration, force "
        "model, conjunction settings, burn-up altitude, progress interval or seed differ)");
  if (c.total_steps != total_steps_of(config))
    throw std::runtime_error("checkpoint: step count does not match the scenario");
  auto sim = std::make_unique<Simulation>(config, std::move(c.population), std::move(parts));
  State& s = *sim->state_;
  s.step = c.step;
  s.next_seq = c.next_seq;
  s.counters = static_cast<const RunCounters&>(c);
  s.wall_before_s = c.wall_s;
  if (!s.events_hash.restore_state(c.events_digest_state))
    throw std::runtime_error("checkpoint: events digest state is malformed");
  for (const auto& e : c.closest_per_pair) s.closest.update(e);
  s.last_checkpoint_step = c.step;
  s.breakups = c.breakups;
  s.traffic = c.traffic;
  s.actives_adopted = true;  // at the fresh run's start, and the checkpoint holds the outcome
  return sim;
}

Simulation::~Simulation() = default;

const Population& Simulation::population() const {
  return state_->population;
}
std::int64_t Simulation::step() const {
  return state_->step;
}
std::int64_t Simulation::total_steps() const {
  return state_->total_steps;
}

std::vector<Encounter> Simulation::closest_encounters() const {
  return state_->closest.entries();
}

std::string Simulation::checkpoint() const {
  return encode_checkpoint(state_->snapshot(state_->wall_before_s));
}

// One call of run(): the loop's steps and what lives only as long as the call (clocks, phase timers,
// the batch's buffers). The run goes on from s.step, a fresh run's 0 or a resumed run's checkpoint.
struct Simulation::RunLoop {
  RunLoop(State& state, EventSink& event_sink, RunControl& run_control);

  // The loop: at each step boundary the controls and checkpoints, then one batch of steps propagated,
  // scanned and emitted; the summary last.
  RunSummary run();

  enum class Boundary { kGo, kPaused, kEnd };
  Boundary at_boundary();
  bool checkpoint_due();
  void write_checkpoint();
  std::size_t propagate_batch();
  void scan_batch(std::size_t steps);
  std::size_t cut_at_collision(std::size_t steps);
  void emit_batch(std::size_t steps);
  void emit_encounters(const std::vector<Encounter>& step_encounters);
  void emit_burn_ups();
  void remove_burn_ups();
  void break_up(const std::vector<Encounter>& step_encounters);
  void emit_breakup(const BreakupReport& report);
  void run_traffic();
  void emit_progress(double t1_s);
  void emit_snapshot();
  RunSummary finish();

  double wall_now() const { return s.wall_before_s + seconds_since(run_start); }

  State& s;
  const SimulationConfig& cfg;
  EventSink& sink;
  RunControl& control;
  const Clock::time_point run_start;
  Clock::time_point last_checkpoint_wall;
  const std::int64_t first_step;
  const std::int64_t progress_every;
  PhaseTimers timers;
  RunSummary summary;

  std::vector<char> flags;
  // What each step asks of the propagator besides the steps in flight's copies: the burn-up flags in
  // the same pass, unless a finder is given.
  const bool flag_in_step;
  // Collisions the detector finds break their objects up (breakups on, on_collision fragment).
  const bool collisions_fragment;
  StepRequest request;
  std::unique_ptr<StepsInFlight> flight;
  std::vector<std::vector<Encounter>> encounters;  // per step of the batch
  std::vector<BurnUp> burned;                      // on the batch's last step
};

Simulation::RunLoop::RunLoop(State& state, EventSink& event_sink, RunControl& run_control)
    : s(state),
      cfg(state.config),
      sink(event_sink),
      control(run_control),
      run_start(Clock::now()),
      last_checkpoint_wall(run_start),
      first_step(state.step),
      progress_every(progress_interval(state.config, state.total_steps)),
      flag_in_step(state.parts.burn_up && !state.parts.find_burn_ups),
      collisions_fragment(state.config.breakups.enabled &&
                          state.config.breakups.on_collision == CollisionResponse::kFragment &&
                          state.parts.scanner != nullptr) {
  if (flag_in_step) {
    request.burn_up_flags = &flags;
    request.burn_up_radius2 = burn_up_radius2(cfg.burn_up_altitude_m);
  }
  // Steps scanned side by side (steps_in_flight.hpp): one per thread, with scanners of their own, where
  // the scanner offers copies; else one at a time.
  if (s.parts.scanner)
    flight = std::make_unique<StepsInFlight>(
        *s.parts.scanner, static_cast<std::size_t>(cfg.scan_steps_at_once), s.population.size(),
        static_cast<std::size_t>(omp_get_max_threads()), s.parts.timelines);
}

RunSummary Simulation::RunLoop::run() {
  // A fresh run's own active payloads join the lifecycle before anything else happens.
  if (!s.actives_adopted) {
    adopt_catalog_actives(cfg.traffic, cfg.seed, s.population, s.traffic);
    s.actives_adopted = true;
  }
  try {
    if (s.step == 0) emit_snapshot();
    for (;;) {
      const Boundary boundary = at_boundary();
      if (boundary == Boundary::kEnd) break;
      if (boundary == Boundary::kPaused) {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
        continue;
      }
      const std::size_t steps = propagate_batch();
      scan_batch(steps);
      emit_batch(cut_at_collision(steps));
    }
  } catch (const std::exception& e) {
    sink.on_failed(e.what());
    throw;
  }
  return finish();
}

// Step boundary: controls, then checkpoints. kEnd: cancelled, stopped at a checkpoint, or all steps done.
Simulation::RunLoop::Boundary Simulation::RunLoop::at_boundary() {
  if (control.cancel.load()) {
    summary.cancelled = true;
    return Boundary::kEnd;
  }
  if (checkpoint_due() && s.step < s.total_steps) write_checkpoint();
  if (control.stop_after_checkpoint.load() && s.step < s.total_steps) {
    summary.cancelled = true;
    summary.stopped_at_checkpoint = true;
    return Boundary::kEnd;
  }
  if (control.pause.load()) return Boundary::kPaused;
  if (s.step >= s.total_steps) return Boundary::kEnd;
  return Boundary::kGo;
}

// Asked for (checkpoint_now, which this clears, or stop_after_checkpoint), or periodic (every
// checkpoint_every_steps steps or checkpoint_every_wall_s seconds) at a boundary inside the run that has
// no checkpoint yet.
bool Simulation::RunLoop::checkpoint_due() {
  const bool fresh_boundary = s.step != s.last_checkpoint_step && s.step > 0 && s.step < s.total_steps;
  bool due = control.checkpoint_now.exchange(false) || control.stop_after_checkpoint.load();
  if (fresh_boundary && cfg.checkpoint_every_steps > 0 && s.step % cfg.checkpoint_every_steps == 0)
    due = true;
  if (fresh_boundary && cfg.checkpoint_every_wall_s > 0 &&
      seconds_since(last_checkpoint_wall) >= cfg.checkpoint_every_wall_s)
    due = true;
  return due;
}

void Simulation::RunLoop::write_checkpoint() {
  auto t0 = Clock::now();
  std::string bytes = encode_checkpoint(s.snapshot(wall_now()));
  sink.on_checkpoint(s.next_seq - 1, s.step, bytes);
  s.last_checkpoint_step = s.step;
  last_checkpoint_wall = Clock::now();
  timers.checkpoint_s += seconds_since(t0);
}

// A batch: up to one step per scanner in flight, ending early at the next checkpoint step and at a step
// where objects burn up (the population then changes: the next batch starts afresh). Each step is
// integrated and its burn-ups found; returns the number of steps.
std::size_t Simulation::RunLoop::propagate_batch() {
  std::int64_t batch_end =
      std::min(s.total_steps, s.step + (flight ? static_cast<std::int64_t>(flight->capacity()) : 1));
  if (cfg.checkpoint_every_steps > 0)
    batch_end = std::min(batch_end, (s.step / cfg.checkpoint_every_steps + 1) * cfg.checkpoint_every_steps);
  // A snapshot needs the population at its boundary: the batch ends there (results never depend on
  // where batches end).
  if (cfg.snapshot_every_steps > 0)
    batch_end = std::min(batch_end, (s.step / cfg.snapshot_every_steps + 1) * cfg.snapshot_every_steps);
  // A breakup changes the population at its boundary, and so does the end of a separation (pairs are
  // screened from then on): the batch ends there. Where collisions fragment, any step may end with a
  // breakup: the batch is cut after such a step (cut_at_collision).
  if (const auto breakup = next_breakup_step(cfg.breakups, s.step, cfg.dt_s))
    batch_end = std::min(batch_end, *breakup);
  if (const auto parted = next_separation_end_step(s.breakups, s.step, cfg.dt_s))
    batch_end = std::min(batch_end, *parted);
  // Launches and ends of life change the population at their boundaries too.
  if (const auto traffic = next_traffic_step(cfg.traffic, s.traffic, s.step, cfg.dt_s))
    batch_end = std::min(batch_end, *traffic);
  Population& pop = s.population;
  end_separations(static_cast<double>(s.step) * cfg.dt_s, pop, s.breakups);
  const std::int64_t batch_start = s.step;
  std::int64_t next = batch_start;
  burned.clear();
  while (next < batch_end && burned.empty()) {
    const double t0_s = static_cast<double>(next) * cfg.dt_s;
    const double t1_s = t0_s + cfg.dt_s;
    // Integrate.
    auto t = Clock::now();
    if (flight) {
      s.parts.propagator->step_with(pop, t0_s, cfg.dt_s,
                                    flight->request_for_next(request, next + 1 == batch_end));
      flight->push(t0_s, cfg.dt_s, s.parts.propagator->last_chunks());
    } else {
      s.parts.propagator->step_with(pop, t0_s, cfg.dt_s, request);
    }
    timers.integrator_s += seconds_since(t);
    // Burn-up: found now, removed after detection (the steps' ends stay index-aligned for the scans).
    t = Clock::now();
    if (s.parts.burn_up) {
      burned = flag_in_step ? flagged_burn_ups(pop, t1_s, flags)
                            : s.parts.find_burn_ups(pop, cfg.burn_up_altitude_m, t1_s, flags);
      std::sort(burned.begin(), burned.end(), [](const BurnUp& a, const BurnUp& b) { return a.id < b.id; });
    }
    timers.burn_up_s += seconds_since(t);
    ++next;
  }
  return static_cast<std::size_t>(next - batch_start);
}

// Detection: every step of the batch scanned, into encounters[j] for step j.
void Simulation::RunLoop::scan_batch(std::size_t steps) {
  Population& pop = s.population;
  for (std::vector<Encounter>& step_encounters : encounters) step_encounters.clear();
  encounters.resize(std::max(encounters.size(), steps));
  if (flight) {
    if (pop.size() > 1) {
      flight->scan(pop, encounters);
      timers.grid_s += flight->last_grid_s();
      timers.detection_s += flight->last_scan_s() - flight->last_grid_s();
    }
    flight->restart();
  }
}

// Where collisions fragment, a collision in step j of the batch ends the batch there: the population
// goes back to the end of step j (the copy the steps in flight kept; the propagator's steps are per
// object, so the steps after are simply taken again from there), and the later steps' encounters and
// burn-ups (found on the batch's last step only) are dropped. Returns the steps kept.
std::size_t Simulation::RunLoop::cut_at_collision(std::size_t steps) {
  if (!collisions_fragment || !flight) return steps;
  for (std::size_t j = 0; j + 1 < steps; ++j) {
    const bool collided = std::any_of(encounters[j].begin(), encounters[j].end(),
                                      [](const Encounter& e) { return e.kind == EncounterKind::kCollision; });
    if (!collided) continue;
    s.population.state = flight->start_of(j + 1);
    burned.clear();
    return j + 1;
  }
  return steps;
}

// Events, step by step, in sequence order: encounters (canonical), burn-ups (by id, on the batch's last
// step, whose objects then leave the population), scheduled breakups (on the batch's last step), progress.
void Simulation::RunLoop::emit_batch(std::size_t steps) {
  auto t = Clock::now();
  for (std::size_t j = 0; j < steps; ++j) {
    const double t1_s = static_cast<double>(s.step + 1) * cfg.dt_s;
    emit_encounters(encounters[j]);
    if (j + 1 == steps) {
      emit_burn_ups();
      remove_burn_ups();
      break_up(encounters[j]);
      run_traffic();
    }
    ++s.step;
    if (s.step % progress_every == 0 || s.step == s.total_steps) emit_progress(t1_s);
  }
  // Batches end at snapshot steps, so the population is at s.step here.
  if (cfg.snapshot_every_steps > 0 && (s.step % cfg.snapshot_every_steps == 0 || s.step == s.total_steps))
    emit_snapshot();
  timers.output_s += seconds_since(t);
}

void Simulation::RunLoop::emit_encounters(const std::vector<Encounter>& step_encounters) {
  for (const Encounter& e : step_encounters) {
    const std::uint64_t seq = s.next_seq++;
    hash_encounter(s.events_hash, seq, e);
    ++s.counters.events;
    if (e.kind == EncounterKind::kEvasion)
      ++s.counters.evasions;
    else
      ++s.counters.conjunctions;
    if (e.kind == EncounterKind::kCollision) ++s.counters.collisions;
    s.closest.update(e);
    sink.on_encounter(seq, e);
  }
}

void Simulation::RunLoop::emit_burn_ups() {
  for (const BurnUp& b : burned) {
    const std::uint64_t seq = s.next_seq++;
    hash_burn_up(s.events_hash, seq, b);
    ++s.counters.events;
    ++s.counters.burn_ups;
    sink.on_burn_up(seq, b);
  }
}

void Simulation::RunLoop::remove_burn_ups() {
  if (!burned.empty()) s.population.remove_flagged(flags);
}

// The breakups at the boundary the batch ends on (s.step + 1): first the step's collisions (canonical
// order; they end a one-step batch) broken up at their times of closest approach, then the scheduled
// events due there (schedule order); each replaces its parents by fragments, one event each. Fragment
// generation counts as burn-up time (the phase that changes the population).
void Simulation::RunLoop::break_up(const std::vector<Encounter>& step_encounters) {
  if (!cfg.breakups.enabled) return;
  auto t = Clock::now();
  const std::int64_t boundary = s.step + 1;
  const double t1_s = static_cast<double>(boundary) * cfg.dt_s;
  if (collisions_fragment) {
    const PropagateObjects propagate = [this](Population& objects, double t_start_s, double t_end_s) {
      s.parts.propagator->step(objects, t_start_s, t_end_s - t_start_s);
    };
    for (const Encounter& e : step_encounters) {
      if (e.kind != EncounterKind::kCollision) continue;
      if (const auto report =
              apply_collision_breakup(cfg.breakups, e, cfg.seed, t1_s, s.population, s.breakups, propagate))
        emit_breakup(*report);
    }
  }
  for (std::size_t index : breakups_due(cfg.breakups, boundary, cfg.dt_s))
    if (const auto report =
            apply_scheduled_breakup(cfg.breakups, index, cfg.seed, t1_s, s.population, s.breakups))
      emit_breakup(*report);
  timers.burn_up_s += seconds_since(t);
}

void Simulation::RunLoop::emit_breakup(const BreakupReport& report) {
  const std::uint64_t seq = s.next_seq++;
  hash_breakup(s.events_hash, seq, report);
  ++s.counters.events;
  sink.on_breakup(seq, report);
}

// The lifecycle at the boundary the batch ends on (s.step + 1): ends of life due (by end, then id), then
// the launches due (plan order); one event each (a launch event per plan row). Counted as burn-up time.
void Simulation::RunLoop::run_traffic() {
  if (!cfg.traffic.enabled) return;
  auto t = Clock::now();
  const std::int64_t boundary = s.step + 1;
  const double t1_s = static_cast<double>(boundary) * cfg.dt_s;
  std::vector<LifecycleReport> reports =
      retire_due(cfg.traffic, cfg.seed, t1_s, cfg.burn_up_altitude_m, s.population, s.traffic);
  for (const LifecycleReport& r : launch_due(cfg.traffic, boundary, cfg.dt_s, s.population, s.traffic))
    reports.push_back(r);
  for (const LifecycleReport& r : reports) {
    const std::uint64_t seq = s.next_seq++;
    hash_lifecycle(s.events_hash, seq, r);
    ++s.counters.events;
    sink.on_lifecycle(seq, r);
  }
  timers.burn_up_s += seconds_since(t);
}

// Progress after step s.step, ending at t1_s.
void Simulation::RunLoop::emit_progress(double t1_s) {
  Progress p;
  p.step = s.step;
  p.total_steps = s.total_steps;
  p.sim_time_s = t1_s;
  p.objects_alive = s.population.size();
  p.objects_by_type = count_by_type(s.population);
  p.events_so_far = s.counters.events;
  p.wall_s = wall_now();
  const double session_wall = seconds_since(run_start);
  const std::int64_t done = s.step - first_step;
  p.eta_s =
      done > 0 ? session_wall / static_cast<double>(done) * static_cast<double>(s.total_steps - s.step) : 0.0;
  const std::uint64_t seq = s.next_seq++;
  hash_progress(s.events_hash, seq, p);
  sink.on_progress(seq, p);
}

// The population now (after s.step steps), when snapshots are on.
void Simulation::RunLoop::emit_snapshot() {
  if (cfg.snapshot_every_steps <= 0) return;
  sink.on_snapshot(std::make_shared<const PopulationSnapshot>(
      take_snapshot(s.population, s.step, static_cast<double>(s.step) * cfg.dt_s)));
}

// The summary, handed to the sink unless the run stopped at a checkpoint (it goes on later).
RunSummary Simulation::RunLoop::finish() {
  timers.total_s = seconds_since(run_start);
  summary.steps = s.step;
  summary.sim_time_s = static_cast<double>(s.step) * cfg.dt_s;
  static_cast<RunCounters&>(summary) = s.counters;
  summary.objects_final = s.population.size();
  summary.events_digest = s.events_hash.hex_digest();
  summary.state_digest = state_digest(s.population);
  summary.timers = timers;
  if (!summary.stopped_at_checkpoint) sink.on_finished(summary);
  return summary;
}

RunSummary Simulation::run(EventSink& sink, RunControl& control) {
  if (state_->config.threads > 0) omp_set_num_threads(state_->config.threads);
  return RunLoop(*state_, sink, control).run();
}

}  // namespace kessler
