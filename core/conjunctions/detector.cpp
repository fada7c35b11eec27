#include "core/conjunctions/detector.hpp"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>

#include "core/conjunctions/broad_phase_grid.hpp"
#include "core/conjunctions/narrow_phase_hermite.hpp"
#include "core/conjunctions/narrow_phase_linear.hpp"
#include "core/conjunctions/pair_rules.hpp"
#include "core/parallel/team_timeline.hpp"

namespace kessler {
namespace {

// The paper's simulation domain: a cube of 20,000 km edge centred on the Earth.
constexpr double kDomainEdge_m = 20.0e6;
// Threshold share used to bound the cutoff when only kappa is known (the radius of a large object).
constexpr double kBoundingRadius_m = 50.0;
// A wait for another thread's sort spins this many pauses (a few microseconds) before it yields the core.
constexpr int kSpinsBeforeYield = 256;

// Waits until done() holds: a short spin, then yielding the core (with more threads than cores, the
// thread being waited for may need this one's).
template <typename Done>
void wait_until(Done done) {
  for (int spins = 0; !done(); ++spins) {
    if (spins < kSpinsBeforeYield) {
#if defined(__x86_64__) || defined(__i386__)
      __builtin_ia32_pause();
#endif
    } else {
      std::this_thread::yield();
    }
  }
}

}  // namespace

ConjunctionDetector::ConjunctionDetector(const ConjunctionSettings& settings, const GridSettings& grid)
    : settings_(settings), grid_(grid) {
  // dt is not known here; any positive step checks everything else.
  if (auto problem = validate(settings, 1.0)) throw std::invalid_argument(*problem);
}

void ConjunctionDetector::set_share(std::size_t part, std::size_t parts) {
  if (parts == 0 || part >= parts)
    throw std::invalid_argument("ConjunctionDetector::set_share: part " + std::to_string(part) + " of " +
                                std::to_string(parts));
  grid_.set_share(part, parts);
}

std::optional<std::string> ConjunctionDetector::validate(const ConjunctionSettings& s, double dt_s) {
  std::ostringstream why;
  if (!(s.kappa_max > 0.0 && s.kappa_max <= 10.0)) {
    why << "kappa_max: must be in (0, 10], got " << s.kappa_max;
    return why.str();
  }
  if (!(s.screening_distance_m >= 0.0) || !std::isfinite(s.screening_distance_m)) {
    why << "screening_distance_m: must be a finite distance >= 0 (0: use kappa_max), got "
        << s.screening_distance_m;
    return why.str();
  }
  if (!(s.active_passive_evasion_efficiency >= 0.0 && s.active_passive_evasion_efficiency <= 1.0)) {
    why << "active_passive_evasion_efficiency: must be in [0, 1], got "
        << s.active_passive_evasion_efficiency;
    return why.str();
  }
  if (!(s.active_passive_max_passive_radius_m >= 0.0)) {
    why << "active_passive_max_passive_radius_m: must be >= 0, got " << s.active_passive_max_passive_radius_m;
    return why.str();
  }
  if (!(dt_s > 0.0) || !std::isfinite(dt_s)) {
    why << "dt_s: the step must be a positive number of seconds, got " << dt_s;
    return why.str();
  }
  // The cutoff: largest displacement in a step plus the largest threshold (broad_phase_grid.hpp).
  const double share =
      s.screening_distance_m > 0.0 ? 0.5 * s.screening_distance_m : s.kappa_max * kBoundingRadius_m;
  const double motion_m = BroadPhaseGrid::cutoff_bound_m(dt_s, 0.0);
  const double cutoff = BroadPhaseGrid::cutoff_bound_m(dt_s, share);
  if (cutoff > kDomainEdge_m) {
    if (s.screening_distance_m > motion_m) {
      why << "screening_distance_m: " << s.screening_distance_m / 1e3 << " km gives a detection cutoff of "
          << cutoff / 1e3 << " km, more than the 20,000 km domain";
    } else {
      why << "dt_s: a step of " << dt_s << " s gives a detection cutoff of " << cutoff / 1e3
          << " km (objects move up to 11.19 km/s), more than the 20,000 km domain";
    }
    return why.str();
  }
  return std::nullopt;
}

void ConjunctionDetector::scan(const Population& population, const StepEnds& step,
                               std::vector<Encounter>& out) {
  if (step.dt_s != validated_dt_s_) {
    if (auto problem = validate(settings_, step.dt_s)) throw std::invalid_argument(*problem);
    validated_dt_s_ = step.dt_s;
  }
  if (step.start == nullptr || step.end == nullptr)
    throw std::invalid_argument("step: start and end states are required");
  const std::size_t n = population.size();
  if (step.start->size() != n || step.end->size() != n)
    throw std::invalid_argument("step: states must be index-aligned with the population");
  last_grid_s_ = last_narrow_s_ = 0.0;
  last_candidate_pairs_ = 0;
  if (n < 2) return;

  const double t_begin = omp_get_wtime();
  ThresholdShare share;
  if (settings_.screening_distance_m > 0.0) {
    share.fixed_m = 0.5 * settings_.screening_distance_m;
  } else {
    share.radius_m = population.radius_m.data();
    share.kappa = settings_.kappa_max;
  }
  // No bound orbit moves further along an axis in a step than this; objects that do are oversized.
  const double max_motion_m = BroadPhaseGrid::cutoff_bound_m(step.dt_s, 0.0) + 1e-3;

  const int threads = n >= kParallelMinimumObjects ? omp_get_max_threads() : 1;
  const bool use_hulls = use_hulls_;
  const std::size_t share_part = grid_.share_part(), share_parts = grid_.share_parts();
  grid_.prepare(n, threads);
  grid_.set_separation_groups(population.separation_group.size() == n ? population.separation_group.data()
                                                                      : nullptr);
  per_thread_.resize(static_cast<std::size_t>(threads));
  // Cleared here: OpenMP may give the region fewer threads than asked for.
  for (ThreadLists& lists : per_thread_) {
    lists.candidates.clear();
    lists.events.clear();
    lists.collected_at = t_begin;
    lists.own_slots = lists.helped_slots = 0;
    lists.walk_s_of.assign(static_cast<std::size_t>(threads), 0.0);
  }
  std::size_t team_size = 0;  // the team OpenMP gave the region
  const bool help = sharing_.helping();
  if (walk_cursors_.size() < static_cast<std::size_t>(threads))
    walk_cursors_ = std::vector<WalkCursor>(static_cast<std::size_t>(threads));
  for (WalkCursor& cursor : walk_cursors_) cursor.claimed.store(0, std::memory_order_relaxed);
  // One region per step: the grid (one barrier inside), then each thread collects its share of
  // candidate pairs into its own compact array and runs the narrow phase on them, with no barrier.
  TeamTimeline* const timeline = step.timeline;
  if (timeline) timeline->region_start(static_cast<std::size_t>(threads));
#pragma omp parallel num_threads(threads)
  {
    const std::size_t t = static_cast<std::size_t>(omp_get_thread_num());
    if (timeline) timeline->enter(t);
    grid_.build_in_team(step, settings_.narrow_phase, share, max_motion_m, use_hulls);
    std::vector<CandidatePair>& mine = per_thread_[t].candidates;
    // The walk: each thread first walks the slots it sorted (its region of space, whose neighbour
    // cells are its own too, so it reads lines its own core wrote), then helps with the others' where
    // that pays (walk_sharing.hpp).
    // No barrier after the sort: a region's slots are walked once that region is sorted (a thread
    // that finds another's not yet sorted goes on to the next, and comes back to it). Runs are claimed
    // as the threads ask (dense regions of the sky cost more), guided: the owner takes half of what is
    // left of its slots, a helper a quarter, at least kMinRun slots (~10 us of walk on one core): few
    // claims, and short runs at the end, when the last ones decide when the team is done.
    constexpr std::size_t kMinRun = 128;
    const std::size_t team = static_cast<std::size_t>(omp_get_num_threads());
    if (t == 0) team_size = team;
    for (std::size_t visit = 0; visit < 2 * team; ++visit) {
      const std::size_t d = visit % team;
      if (d != 0 && !help) continue;
      const std::size_t owner = (t + d) % team;
      if (!grid_.slots_sorted(owner, team)) {
        if (visit < team) continue;  // first round: come back to it
        wait_until([&] { return grid_.slots_sorted(owner, team); });
      }
      // The owner's run lies in this detector's share of the grid (set_share).
      const auto [first, last] = grid_.sorted_slots(owner, team);
      std::atomic<std::size_t>& claimed = walk_cursors_[owner].claimed;
      const std::size_t divisor = d == 0 ? 2 : 4;
      const double visit_start = omp_get_wtime();
      std::size_t walked = 0;
      for (std::size_t taken = claimed.load(std::memory_order_relaxed);;) {
        const std::size_t left = last - first - std::min(taken, last - first);
        if (left == 0) break;
        const std::size_t run = std::min(left, std::max(left / divisor, kMinRun));
        if (!claimed.compare_exchange_weak(taken, taken + run, std::memory_order_relaxed)) continue;
        grid_.collect_pairs(first + taken, first + taken + run, mine);
        walked += run;
        taken = claimed.load(std::memory_order_relaxed);
      }
      if (walked > 0) {
        ThreadLists& me = per_thread_[t];
        (d == 0 ? me.own_slots : me.helped_slots) += walked;
        me.walk_s_of[owner] += omp_get_wtime() - visit_start;
      }
    }
    const std::int64_t oversized = static_cast<std::int64_t>(grid_.oversized_count());
#pragma omp for schedule(dynamic, 1) nowait
    for (std::int64_t o = 0; o < oversized; ++o)
      if (static_cast<std::size_t>(o) % share_parts == share_part)
        grid_.collect_oversized_pairs(static_cast<std::size_t>(o), static_cast<std::size_t>(o) + 1, mine);
    per_thread_[t].collected_at = omp_get_wtime();
    if (timeline) timeline->mark(t, kDetWalk);
    std::vector<Encounter>& found = per_thread_[t].events;
    if (use_hulls) {
      // The hulls first (one cache line per object, at two random places in memory: ask for a pair's
      // hulls a few pairs ahead so their loads overlap); the states only for pairs they keep.
      constexpr std::size_t kAhead = 16;
      for (std::size_t p = 0; p < mine.size(); ++p) {
        if (p + kAhead < mine.size()) {
          __builtin_prefetch(&grid_.hull(mine[p + kAhead].i));
          __builtin_prefetch(&grid_.hull(mine[p + kAhead].j));
        }
        if (hulls_may_come_within(grid_.hull(mine[p].i), grid_.hull(mine[p].j)))
          examine_pair(population, step, mine[p].i, mine[p].j, found);
      }
    } else {
      for (const CandidatePair& pair : mine) examine_pair(population, step, pair.i, pair.j, found);
    }
    if (timeline) timeline->mark(t, kDetNarrow);
  }
  if (timeline) timeline->region_end();
  double t_grid = t_begin;
  std::size_t total = 0, pairs = 0;
  for (const ThreadLists& lists : per_thread_) {
    t_grid = std::max(t_grid, lists.collected_at);
    total += lists.events.size();
    pairs += lists.candidates.size();
  }
  if (threads > 1 && team_size == static_cast<std::size_t>(threads)) {
    std::size_t own_slots = 0, helped_slots = 0;
    double own_s = 0.0, helped_s = 0.0;
    // Each thread's run of slots (its region, with a thread per region): its sort and all its walks.
    std::vector<double>& cost = region_cost_s_;
    cost.assign(team_size, 0.0);
    for (std::size_t u = 0; u < team_size; ++u) {
      const ThreadLists& lists = per_thread_[u];
      own_slots += lists.own_slots;
      helped_slots += lists.helped_slots;
      cost[u] += grid_.last_sort_s(u);
      for (std::size_t w = 0; w < team_size; ++w) {
        cost[w] += lists.walk_s_of[w];
        (w == u ? own_s : helped_s) += lists.walk_s_of[w];
      }
    }
    sharing_.record(own_slots, own_s, helped_slots, helped_s);
    // A shared scan's parts must lay out the same grid (set_share): no measured costs move its borders.
    if (share_parts == 1) {
      grid_.record_region_costs(cost.data(), team_size);
      grid_.record_pass_costs(team_size);  // each thread's passes over its chunk, for the next chunks
    }
  }
  const std::size_t first = out.size();
  out.reserve(first + total);
  for (const ThreadLists& lists : per_thread_)
    out.insert(out.end(), lists.events.begin(), lists.events.end());
  std::sort(out.begin() + static_cast<std::ptrdiff_t>(first), out.end(), canonical_less);
  const double t_end = omp_get_wtime();
  last_grid_s_ = t_grid - t_begin;
  last_narrow_s_ = t_end - t_grid;
  last_candidate_pairs_ = pairs;
  last_team_size_ = team_size;
  // Writing the hulls costs about as much as gathering the states of 0.3 candidate pairs per object on
  // one thread. With more, most gathers read states another core has just written (several times
  // dearer), and the hulls pay from fewer pairs: 0.3 per object over the thread count.
  constexpr double kHullsFromPairsPerObject = 0.3;
  const double hulls_from = kHullsFromPairsPerObject / static_cast<double>(threads);
  use_hulls_ = settings_.narrow_phase == NarrowPhase::kHermite &&
               static_cast<double>(pairs) >= hulls_from * static_cast<double>(n);
}

void ConjunctionDetector::examine_pair(const Population& population, const StepEnds& step, std::size_t i,
                                       std::size_t j, std::vector<Encounter>& found) const {
  // The lower id is object 1, so a pair's numbers never depend on where or by whom it was found.
  if (population.id[j] < population.id[i]) std::swap(i, j);
  const ObjectStep a = gather_object_step(*step.start, *step.end, i);
  const ObjectStep b = gather_object_step(*step.start, *step.end, j);
  const double r_sum = population.radius_m[i] + population.radius_m[j];
  const double threshold =
      settings_.screening_distance_m > 0.0 ? settings_.screening_distance_m : settings_.kappa_max * r_sum;
  PairMinimum minima[kMaxMinimaPerStep];
  const bool hermite = settings_.narrow_phase == NarrowPhase::kHermite;
  const int count = hermite ? hermite_minima(a, b, step.dt_s, threshold, minima)
                            : linear_minimum(a, b, step.dt_s, threshold, minima);
  for (int m = 0; m < count; ++m) {
    Encounter e;
    e.id1 = population.id[i];
    e.id2 = population.id[j];
    e.tca_s = step.t_start_s + minima[m].tau_s;
    e.miss_distance_m = minima[m].distance_m;
    e.kappa = r_sum > 0.0 ? minima[m].distance_m / r_sum : INFINITY;
    double r1[3], v1[3], r2[3], v2[3];
    if (hermite) {
      hermite_state(a, step.dt_s, minima[m].tau_s, r1, v1);
      hermite_state(b, step.dt_s, minima[m].tau_s, r2, v2);
    } else {
      linear_state(a, minima[m].tau_s, r1, v1);
      linear_state(b, minima[m].tau_s, r2, v2);
    }
    e.r1_m = {r1[0], r1[1], r1[2]};
    e.v1_m_s = {v1[0], v1[1], v1[2]};
    e.r2_m = {r2[0], r2[1], r2[2]};
    e.v2_m_s = {v2[0], v2[1], v2[2]};
    e.relative_speed_m_s = (e.v1_m_s - e.v2_m_s).norm();
    e.kind = classify_encounter(settings_, population.status[i], population.radius_m[i], population.status[j],
                                population.radius_m[j], minima[m].distance_m,
                                evasion_draw(settings_, e.id1, e.id2, e.tca_s));
    found.push_back(e);
  }
}

}  // namespace kessler
