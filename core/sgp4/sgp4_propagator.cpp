#include "core/sgp4/sgp4_propagator.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace kessler {

Sgp4Propagator::Sgp4Propagator(const std::vector<ObjectId>& ids, const std::vector<MeanElements>& elements,
                               const UtcEpoch& scenario_epoch) {
  if (ids.size() != elements.size())
    throw std::invalid_argument("Sgp4Propagator: " + std::to_string(ids.size()) + " ids but " +
                                std::to_string(elements.size()) + " element sets");
  records_.resize(elements.size());
  offset_min_.resize(elements.size());
#pragma omp parallel for schedule(dynamic, 256)
  for (std::size_t i = 0; i < elements.size(); ++i) {
    records_[i] = sgp4_initialise(elements[i]);
    offset_min_[i] = scenario_epoch.seconds_since(elements[i].epoch) / 60.0;
  }
  for (std::size_t i = 0; i < ids.size(); ++i)
    if (!slot_of_.emplace(ids[i], i).second)
      throw std::invalid_argument("Sgp4Propagator: object " + std::to_string(ids[i]) +
                                  " has two element sets");
}

void Sgp4Propagator::sync(const Population& population) {
  if (synced_ids_ == population.id && batch_.size() == population.size()) return;
  const std::size_t n = population.size();
  std::vector<Sgp4Record> ordered(n);
  batch_offset_min_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    auto it = slot_of_.find(population.id[i]);
    if (it == slot_of_.end())
      throw std::invalid_argument("Sgp4Propagator: object " + std::to_string(population.id[i]) + " (" +
                                  population.name[i] + ") has no element set");
    ordered[i] = records_[it->second];
    batch_offset_min_[i] = offset_min_[it->second];
  }
  batch_.assign(ordered);
  synced_ids_ = population.id;
  for (auto* v : {&minutes_, &x_, &y_, &z_, &vx_, &vy_, &vz_}) v->resize(n);
  errors_.resize(n);
}

void Sgp4Propagator::set_states(Population& population, double t_s) {
  if (!std::isfinite(t_s)) throw std::invalid_argument("Sgp4Propagator: time is not finite");
  sync(population);
  const std::size_t n = population.size();
  for (std::size_t i = 0; i < n; ++i) minutes_[i] = batch_offset_min_[i] + t_s / 60.0;
  batch_.propagate_all(minutes_.data(), {x_.data(), y_.data(), z_.data(), vx_.data(), vy_.data(), vz_.data(),
                                         1000.0, 1000.0, errors_.data()});
  failures_.clear();
  StateArrays& s = population.state;
  for (std::size_t i = 0; i < n; ++i) {
    if (errors_[i] != Sgp4Error::kNone && errors_[i] != Sgp4Error::kDecayed) {
      failures_.push_back({population.id[i], errors_[i]});
      continue;
    }
    s.x[i] = x_[i];
    s.y[i] = y_[i];
    s.z[i] = z_[i];
    s.vx[i] = vx_[i];
    s.vy[i] = vy_[i];
    s.vz[i] = vz_[i];
  }
}

void Sgp4Propagator::step(Population& population, double t_start_s, double dt_s) {
  set_states(population, t_start_s + dt_s);
}

}  // namespace kessler
