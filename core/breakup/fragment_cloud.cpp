#include "core/breakup/fragment_cloud.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/breakup/area_to_mass.hpp"
#include "core/breakup/ejection_velocity.hpp"
#include "core/breakup/energy_and_count.hpp"
#include "core/breakup/size_distribution.hpp"
#include "core/population/counter_random.hpp"

namespace kessler {
namespace {

constexpr double kLn10 = 2.302585092994046;
constexpr double kTwoPi = 2.0 * 3.14159265358979323846;

void resize(FragmentCloud& c, std::size_t n) {
  c.draw_index.resize(n);
  c.parent_index.resize(n);
  c.characteristic_length_m.resize(n);
  c.area_to_mass_m2_kg.resize(n);
  c.area_m2.resize(n);
  c.mass_kg.resize(n);
  c.radius_m.resize(n);
  c.delta_v_m_s.resize(n);
  c.velocity_m_s.resize(n);
  c.position_m.resize(n);
}

// Every fragment's values from its own draws: (seed, event id, draw index i, purpose) and nothing else.
void draw_fragments(const BreakupEvent& event, const BreakupPlan& plan, FragmentCloud& c) {
  const std::uint64_t seed = event.seed, id = event.event_id;
  const auto n = static_cast<std::int64_t>(plan.count);
  const TruncatedPowerLaw law(plan.lc_min_m, plan.lc_max_m, plan.size_exponent);
  const SizeStrata strata(plan.count, random_bits(seed, id, RandomPurpose::kBreakupSize, ~0ULL));
  const bool collision = event.kind == BreakupKind::kCollision;
  // Collisions: a fragment comes from parents[0] with probability m0 / (m0 + m1).
  const double weight0 =
      collision ? event.parents[0].mass_kg / (event.parents[0].mass_kg + event.parents[1].mass_kg) : 1.0;
  const BreakupParent* parents = event.parents.data();
#pragma omp parallel for schedule(static)
  for (std::int64_t s = 0; s < n; ++s) {
    const auto i = static_cast<std::uint64_t>(s);
    const double u_size = strata.uniform(i, random_uniform(seed, id, RandomPurpose::kBreakupSize, i));
    const double log_lc = law.log_size(u_size);
    const double lc = std::exp(log_lc);
    const double lambda = log_lc / kLn10;
    const std::uint8_t p = random_uniform(seed, id, RandomPurpose::kBreakupParent, i) < weight0 ? 0 : 1;
    const BreakupParent& parent = parents[p];
    // One Box-Muller pair: its cosine for A/m, its sine for the ejection speed (independent normals).
    const double r =
        std::sqrt(-2.0 * std::log(random_uniform(seed, id, RandomPurpose::kBreakupNormal, 2 * i)));
    const double theta = kTwoPi * random_uniform(seed, id, RandomPurpose::kBreakupNormal, 2 * i + 1);
    const double z_am = r * std::cos(theta), z_dv = r * std::sin(theta);
    const double chi = sample_log_area_to_mass(
        lc, lambda, parent.object_class,
        random_uniform(seed, id, RandomPurpose::kBreakupAreaToMassBranch, 2 * i),
        random_uniform(seed, id, RandomPurpose::kBreakupAreaToMassBranch, 2 * i + 1), z_am);
    const double area = area_from_log_size(log_lc);
    const double log_dv = mean_log_ejection_speed(event.kind, chi) + kLogEjectionSpeedSigma * z_dv;
    const double dv = std::exp(kLn10 * log_dv);
    const std::array<double, 3> dir =
        isotropic_direction(random_uniform(seed, id, RandomPurpose::kBreakupDirection, 2 * i),
                            random_uniform(seed, id, RandomPurpose::kBreakupDirection, 2 * i + 1));
    c.draw_index[i] = i;
    c.parent_index[i] = p;
    c.characteristic_length_m[i] = lc;
    c.radius_m[i] = 0.5 * lc;
    c.area_m2[i] = area;
    c.area_to_mass_m2_kg[i] = std::exp(kLn10 * chi);
    c.mass_kg[i] = area / c.area_to_mass_m2_kg[i];
    c.delta_v_m_s.x[i] = dv * dir[0];
    c.delta_v_m_s.y[i] = dv * dir[1];
    c.delta_v_m_s.z[i] = dv * dir[2];
    c.velocity_m_s.x[i] = parent.velocity_m_s[0] + dv * dir[0];
    c.velocity_m_s.y[i] = parent.velocity_m_s[1] + dv * dir[1];
    c.velocity_m_s.z[i] = parent.velocity_m_s[2] + dv * dir[2];
    c.position_m.x[i] = parent.position_m[0];
    c.position_m.y[i] = parent.position_m[1];
    c.position_m.z[i] = parent.position_m[2];
  }
}

void move_fragment(FragmentCloud& c, std::size_t from, std::size_t to) {
  c.draw_index[to] = c.draw_index[from];
  c.parent_index[to] = c.parent_index[from];
  c.characteristic_length_m[to] = c.characteristic_length_m[from];
  c.area_to_mass_m2_kg[to] = c.area_to_mass_m2_kg[from];
  c.area_m2[to] = c.area_m2[from];
  c.mass_kg[to] = c.mass_kg[from];
  c.radius_m[to] = c.radius_m[from];
  for (Vec3Arrays* v : {&c.delta_v_m_s, &c.velocity_m_s, &c.position_m}) {
    v->x[to] = v->x[from];
    v->y[to] = v->y[from];
    v->z[to] = v->z[from];
  }
}

// Mass conservation: when the drawn fragments weigh more than the parents, the heaviest are dropped
// (heaviest first, ties by draw index) until the rest weigh no more than the parents. The model's mass
// excess sits in its few largest fragments, so this drops few fragments and leaves the size and A/m laws
// below them untouched. Sequential on the drawn values: the same result on any thread count.
void keep_within_parent_mass(FragmentCloud& c) {
  double total = 0.0;
  for (double m : c.mass_kg) total += m;
  if (total <= c.parent_mass_kg) return;
  std::vector<std::pair<double, std::uint64_t>> heap(c.size());
  for (std::size_t i = 0; i < c.size(); ++i) heap[i] = {c.mass_kg[i], c.draw_index[i]};
  std::make_heap(heap.begin(), heap.end());
  std::vector<bool> dropped(c.size(), false);
  while (total > c.parent_mass_kg && !heap.empty()) {
    std::pop_heap(heap.begin(), heap.end());
    total -= heap.back().first;
    dropped[heap.back().second] = true;  // draw_index == position before any drop
    heap.pop_back();
  }
  std::size_t kept = 0;
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (dropped[i]) continue;
    if (kept != i) move_fragment(c, i, kept);
    ++kept;
  }
  resize(c, kept);
}

// The target of a non-catastrophic collision survives. With mass conservation it takes the parents'
// mass less the fragments' and the velocity that makes the event's momentum exact; without, it keeps
// its own mass and velocity.
void add_remnant(const BreakupEvent& event, const BreakupPlan& plan, FragmentCloud& c) {
  const BreakupParent& target = event.parents[plan.target];
  BreakupRemnant r;
  r.parent_id = target.id;
  r.parent_index = static_cast<std::uint8_t>(plan.target);
  r.characteristic_length_m = target.characteristic_length_m;
  r.radius_m = 0.5 * target.characteristic_length_m;
  r.position_m = target.position_m;
  r.mass_kg = target.mass_kg;
  r.velocity_m_s = target.velocity_m_s;
  if (event.conserve_mass) {
    r.mass_kg = c.parent_mass_kg - c.fragment_mass_kg;
    if (r.mass_kg <= 0.0) return;  // the fragments took everything: no remnant
    std::array<double, 3> momentum{};
    for (const BreakupParent& p : event.parents)
      for (int k = 0; k < 3; ++k) momentum[k] += p.mass_kg * p.velocity_m_s[k];
    const std::vector<double>* v[3] = {&c.velocity_m_s.x, &c.velocity_m_s.y, &c.velocity_m_s.z};
    for (int k = 0; k < 3; ++k) {
      for (std::size_t i = 0; i < c.size(); ++i) momentum[k] -= c.mass_kg[i] * (*v[k])[i];
      r.velocity_m_s[k] = momentum[k] / r.mass_kg;
    }
  }
  c.remnant = r;
}

}  // namespace

void generate_fragments(const BreakupEvent& event, FragmentCloud& c) {
  const BreakupPlan plan = plan_breakup(event);
  c.remnant.reset();
  c.catastrophic = plan.catastrophic;
  c.specific_energy_j_per_g = plan.specific_energy_j_per_g;
  c.impact_speed_m_s = plan.impact_speed_m_s;
  c.expected_count = plan.expected_count;
  c.drawn_count = plan.count;
  c.parent_mass_kg = 0.0;
  for (const BreakupParent& p : event.parents) c.parent_mass_kg += p.mass_kg;
  resize(c, plan.count);
  draw_fragments(event, plan, c);
  if (event.conserve_mass) keep_within_parent_mass(c);
  c.fragment_mass_kg = 0.0;
  for (double m : c.mass_kg) c.fragment_mass_kg += m;
  if (!plan.catastrophic) add_remnant(event, plan, c);
  c.unresolved_mass_kg = c.parent_mass_kg - c.fragment_mass_kg - (c.remnant ? c.remnant->mass_kg : 0.0);
}

FragmentCloud generate_fragments(const BreakupEvent& event) {
  FragmentCloud c;
  generate_fragments(event, c);
  return c;
}

}  // namespace kessler
