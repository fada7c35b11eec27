#include "core/breakup/fragment_cloud.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/breakup/area_to_mass.hpp"
#include "core/breakup/ejection_velocity.hpp"
#include "core/breakup/energy_and_count.hpp"
#include "core/breakup/size_distribution.hpp"
#include "core/random/counter_random.hpp"

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
  // Collisions: parents[0] takes the share w0 = m0 / (m0 + m1) of the strata, spread evenly over the
  // sizes (a Sturmian sequence in stratum order with a random phase), so that each parent gets its mass
  // share of the fragments at every size: the mass sits in the largest few, and independent choices
  // would leave the momentum to chance among them.
  const double weight0 =
      collision ? event.parents[0].mass_kg / (event.parents[0].mass_kg + event.parents[1].mass_kg) : 1.0;
  const double phase = random_uniform(seed, id, RandomPurpose::kBreakupParent, 0);
  const BreakupParent* parents = event.parents.data();
#pragma omp parallel for schedule(static)
  for (std::int64_t s = 0; s < n; ++s) {
    const auto i = static_cast<std::uint64_t>(s);
    const std::uint64_t stratum = strata.stratum(i);
    const double u_size = strata.uniform(stratum, random_uniform(seed, id, RandomPurpose::kBreakupSize, i));
    const double log_lc = law.log_size(u_size);
    const double lc = std::exp(log_lc);
    const double lambda = log_lc / kLn10;
    const auto sd = static_cast<double>(stratum);
    const std::uint8_t p =
        std::floor((sd + 1.0) * weight0 + phase) > std::floor(sd * weight0 + phase) ? 0 : 1;
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

// Removes the entries at `drop` (ascending positions) from v, keeping the others' order.
template <typename T>
void erase_positions(std::vector<T>& v, const std::vector<std::size_t>& drop) {
  auto out = v.begin() + static_cast<std::ptrdiff_t>(drop[0]);
  for (std::size_t k = 0; k < drop.size(); ++k) {
    const std::size_t end = k + 1 < drop.size() ? drop[k + 1] : v.size();
    out = std::copy(v.begin() + static_cast<std::ptrdiff_t>(drop[k] + 1),
                    v.begin() + static_cast<std::ptrdiff_t>(end), out);
  }
  v.erase(out, v.end());
}

// The `k` heaviest fragments (heaviest first; on equal masses the lower position first).
std::vector<std::pair<double, std::size_t>> heaviest(const std::vector<double>& mass, std::size_t k) {
  auto heavier = [](const std::pair<double, std::size_t>& a, const std::pair<double, std::size_t>& b) {
    return a.first > b.first || (a.first == b.first && a.second < b.second);
  };
  std::vector<std::pair<double, std::size_t>> top;  // a heap whose front is the lightest kept
  top.reserve(k + 1);
  for (std::size_t i = 0; i < mass.size(); ++i) {
    if (top.size() == k && !heavier({mass[i], i}, top.front())) continue;
    top.emplace_back(mass[i], i);
    std::push_heap(top.begin(), top.end(), heavier);
    if (top.size() > k) {
      std::pop_heap(top.begin(), top.end(), heavier);
      top.pop_back();
    }
  }
  std::sort(top.begin(), top.end(), heavier);
  return top;
}

// Mass conservation: when the drawn fragments weigh more than the parents, the heaviest are dropped
// (heaviest first, ties by draw index) until the rest weigh no more than the parents. The model's mass
// excess sits in its few largest fragments, so this drops few fragments and leaves the size and A/m laws
// below them untouched. Sequential on the drawn values: the same result on any thread count.
void keep_within_parent_mass(FragmentCloud& c) {
  double total = 0.0;
  for (double m : c.mass_kg) total += m;
  if (total <= c.parent_mass_kg) return;
  std::vector<std::size_t> drop;
  for (std::size_t k = 8; drop.empty(); k *= 4) {  // look at the k heaviest; more if they do not suffice
    double left = total;
    for (const auto& [mass, i] : heaviest(c.mass_kg, k)) {
      if (left <= c.parent_mass_kg) break;
      left -= mass;
      drop.push_back(i);
    }
    if (left > c.parent_mass_kg && drop.size() < c.size()) drop.clear();
  }
  std::sort(drop.begin(), drop.end());
  erase_positions(c.draw_index, drop);
  erase_positions(c.parent_index, drop);
  for (std::vector<double>* v :
       {&c.characteristic_length_m, &c.area_to_mass_m2_kg, &c.area_m2, &c.mass_kg, &c.radius_m,
        &c.delta_v_m_s.x, &c.delta_v_m_s.y, &c.delta_v_m_s.z, &c.velocity_m_s.x, &c.velocity_m_s.y,
        &c.velocity_m_s.z, &c.position_m.x, &c.position_m.y, &c.position_m.z})
    erase_positions(*v, drop);
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
