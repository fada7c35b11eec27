// Stand-ins for the project's propagator, detector and burn-up rule: simple, per-object (or per-pair)
// and thread-count independent, so the loop's determinism and checkpoints can be tested on their own.
#pragma once

#include <omp.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <random>
#include <vector>

#include "core/simulation/events.hpp"
#include "core/simulation/simulation.hpp"

namespace kessler::testing {

inline constexpr double kMu_m3_s2 = 3.986004418e14;
inline constexpr double kEarthRadius_m = 6378137.0;

// Two-body motion by classical RK4 with 4 substeps per step; each object on its own.
class KeplerRk4Propagator final : public Propagator {
 public:
  void step(Population& p, double, double dt_s) override {
    const long n = static_cast<long>(p.size());
#pragma omp parallel for schedule(static)
    for (long i = 0; i < n; ++i) {
      Eigen::Vector3d r = p.state.position(i), v = p.state.velocity(i);
      const double h = dt_s / 4;
      for (int k = 0; k < 4; ++k) {
        auto acc = [](const Eigen::Vector3d& x) {
          return Eigen::Vector3d(-kMu_m3_s2 / std::pow(x.norm(), 3) * x);
        };
        Eigen::Vector3d k1r = v, k1v = acc(r);
        Eigen::Vector3d k2r = v + 0.5 * h * k1v, k2v = acc(r + 0.5 * h * k1r);
        Eigen::Vector3d k3r = v + 0.5 * h * k2v, k3v = acc(r + 0.5 * h * k2r);
        Eigen::Vector3d k4r = v + h * k3v, k4v = acc(r + h * k3r);
        r += h / 6 * (k1r + 2 * k2r + 2 * k3r + k4r);
        v += h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
      }
      p.state.set(i, r, v);
    }
  }
};

// Every pair, straight-line closest approach inside [0, dt), threshold an absolute distance. Each
// thread collects its own pairs; the merge sorts canonically.
class BruteForceScanner final : public EncounterScanner {
 public:
  explicit BruteForceScanner(double threshold_m) : threshold_m_(threshold_m) {}
  std::unique_ptr<EncounterScanner> another() const override {
    return std::make_unique<BruteForceScanner>(threshold_m_);
  }
  void scan(const Population& p, const StepEnds& step, std::vector<Encounter>& out) override {
    const long n = static_cast<long>(p.size());
    std::vector<std::vector<Encounter>> found(omp_get_max_threads());
#pragma omp parallel for schedule(dynamic, 8)
    for (long i = 0; i < n; ++i) {
      auto& mine = found[omp_get_thread_num()];
      for (long j = i + 1; j < n; ++j) {
        Eigen::Vector3d d0 = step.start->position(i) - step.start->position(j);
        Eigen::Vector3d d1 = step.end->position(i) - step.end->position(j);
        Eigen::Vector3d dv = (d1 - d0) / step.dt_s;
        double tau = dv.squaredNorm() > 0 ? -d0.dot(dv) / dv.squaredNorm() : 0.0;
        if (!(tau > 0.0 && tau < step.dt_s)) continue;  // interior minima only: each reported once
        Eigen::Vector3d d = d0 + tau * dv;
        double miss = d.norm();
        if (miss > threshold_m_) continue;
        Encounter e;
        bool swap = p.id[i] > p.id[j];
        long a = swap ? j : i, b = swap ? i : j;
        e.id1 = p.id[a];
        e.id2 = p.id[b];
        e.tca_s = step.t_start_s + tau;
        e.miss_distance_m = miss;
        e.relative_speed_m_s = dv.norm();
        double rsum = p.radius_m[a] + p.radius_m[b];
        e.kappa = miss / rsum;
        e.kind = miss <= rsum ? EncounterKind::kCollision : EncounterKind::kConjunction;
        if (e.kind == EncounterKind::kConjunction && p.status[a] == ObjectStatus::kActive &&
            p.status[b] == ObjectStatus::kActive)
          e.kind = EncounterKind::kEvasion;
        double f = tau / step.dt_s;
        e.r1_m = (1 - f) * step.start->position(a) + f * step.end->position(a);
        e.r2_m = (1 - f) * step.start->position(b) + f * step.end->position(b);
        e.v1_m_s = step.end->velocity(a);
        e.v2_m_s = step.end->velocity(b);
        mine.push_back(e);
      }
    }
    std::size_t first = out.size();
    for (auto& f : found) out.insert(out.end(), f.begin(), f.end());
    std::sort(out.begin() + first, out.end(), canonical_less);
  }

 private:
  double threshold_m_;
};

inline std::vector<BurnUp> altitude_burn_ups(const Population& p, double min_altitude_m, double time_s,
                                             std::vector<char>& flags) {
  std::vector<BurnUp> out;
  flags.assign(p.size(), 0);
  for (std::size_t i = 0; i < p.size(); ++i) {
    double alt = p.state.position(i).norm() - kEarthRadius_m;
    if (alt < min_altitude_m) {
      flags[i] = 1;
      out.push_back({p.id[i], time_s, alt});
    }
  }
  return out;
}

inline SimulationParts test_parts(double threshold_m = 20e3) {
  SimulationParts parts;
  parts.propagator = std::make_unique<KeplerRk4Propagator>();
  parts.scanner = std::make_unique<BruteForceScanner>(threshold_m);
  parts.find_burn_ups = &altitude_burn_ups;
  return parts;
}

// `n` objects on circular orbits in a thin shell (crowded enough for encounters in a few hundred steps)
// and a few on orbits whose perigee lies below the burn-up altitude.
inline Population test_population(int n, std::uint64_t seed = 7) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Population p;
  for (int k = 0; k < n; ++k) {
    ObjectRecord o;
    o.id = 1000 + 3 * static_cast<ObjectId>(k);
    o.name = "OBJ " + std::to_string(k);
    const bool decaying = k % 40 == 0;
    double a = kEarthRadius_m + (decaying ? 170e3 : 800e3 + 4e3 * u(rng));
    double inc = 1.2 * u(rng), raan = 0.3 * u(rng), arg = 0.6 * u(rng);
    Eigen::Vector3d r_orb(a * std::cos(arg), a * std::sin(arg), 0.0);
    double speed = std::sqrt(kMu_m3_s2 / a) * (decaying ? 0.995 : 1.0);
    Eigen::Vector3d v_orb(-speed * std::sin(arg), speed * std::cos(arg), 0.0);
    Eigen::Matrix3d rot =
        (Eigen::AngleAxisd(raan, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(inc, Eigen::Vector3d::UnitX()))
            .toRotationMatrix();
    o.position_m = rot * r_orb;
    o.velocity_m_s = rot * v_orb;
    o.radius_m = 0.5 + u(rng);
    o.mass_kg = 100;
    o.status = k % 5 == 0 ? ObjectStatus::kActive : ObjectStatus::kPassive;
    p.add(o);
  }
  return p;
}

inline SimulationConfig test_config(std::int64_t steps = 240, int threads = 1) {
  SimulationConfig c;
  c.dt_s = 10.0;
  c.duration_s = 10.0 * static_cast<double>(steps);
  c.progress_every_steps = 10;
  c.threads = threads;
  return c;
}

inline Encounter blank_encounter() {
  Encounter e;
  e.r1_m = e.v1_m_s = e.r2_m = e.v2_m_s = Eigen::Vector3d::Zero();
  return e;
}

// Every event as it arrived, for exact comparison.
struct RecordedEvent {
  std::uint64_t seq;
  int type;  // 0 encounter, 1 burn-up, 2 progress
  Encounter encounter = blank_encounter();
  BurnUp burn_up;
  Progress progress;
};

inline bool same_bits(const RecordedEvent& a, const RecordedEvent& b) {
  if (a.seq != b.seq || a.type != b.type) return false;
  if (a.type == 0) {
    const Encounter &x = a.encounter, &y = b.encounter;
    return x.id1 == y.id1 && x.id2 == y.id2 && x.tca_s == y.tca_s && x.miss_distance_m == y.miss_distance_m &&
           x.relative_speed_m_s == y.relative_speed_m_s && x.kappa == y.kappa && x.kind == y.kind &&
           x.r1_m == y.r1_m && x.r2_m == y.r2_m && x.v1_m_s == y.v1_m_s && x.v2_m_s == y.v2_m_s;
  }
  if (a.type == 1)
    return a.burn_up.id == b.burn_up.id && a.burn_up.time_s == b.burn_up.time_s &&
           a.burn_up.altitude_m == b.burn_up.altitude_m;
  return a.progress.step == b.progress.step && a.progress.sim_time_s == b.progress.sim_time_s &&
         a.progress.objects_alive == b.progress.objects_alive &&
         a.progress.events_so_far == b.progress.events_so_far;
}

struct Checkpoint {
  std::uint64_t last_seq;
  std::int64_t step;
  std::string bytes;
};

class RecordingSink : public EventSink {
 public:
  std::vector<RecordedEvent> events;
  std::vector<Checkpoint> checkpoints;
  std::optional<RunSummary> finished;
  std::string failure;

  void on_encounter(std::uint64_t seq, const Encounter& e) override { events.push_back({seq, 0, e, {}, {}}); }
  void on_burn_up(std::uint64_t seq, const BurnUp& b) override {
    events.push_back({seq, 1, blank_encounter(), b, {}});
  }
  void on_progress(std::uint64_t seq, const Progress& p) override {
    events.push_back({seq, 2, blank_encounter(), {}, p});
  }
  void on_checkpoint(std::uint64_t last_seq, std::int64_t step, const std::string& bytes) override {
    checkpoints.push_back({last_seq, step, bytes});
  }
  void on_finished(const RunSummary& s) override { finished = s; }
  void on_failed(const std::string& reason) override { failure = reason; }
};

}  // namespace kessler::testing
