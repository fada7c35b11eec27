// SGP4 as the scenario's propagator: every object moves by SGP4 from its own element set (short-term
// screening, as SOCRATES does), in TEME of date, m and m/s. Objects are looked up by id, so removing
// objects from the population (burn-ups) keeps working.
#pragma once

#include <unordered_map>
#include <utility>
#include <vector>

#include "core/integration/propagator.hpp"
#include "core/sgp4/mean_elements.hpp"
#include "core/sgp4/sgp4_batch.hpp"

namespace kessler {

class Sgp4Propagator final : public Propagator {
 public:
  // elements[i] belongs to object ids[i]; scenario_epoch is simulation time 0. Throws
  // std::invalid_argument when the lengths differ or an id repeats.
  Sgp4Propagator(const std::vector<ObjectId>& ids, const std::vector<MeanElements>& elements,
                 const UtcEpoch& scenario_epoch);

  // Sets every object's state to its SGP4 state at t_start_s + dt_s. Objects SGP4 cannot propagate
  // keep their previous state and are listed in failures(); a decayed object gets its (sub-surface)
  // SGP4 state so that burn-up detection removes it. Throws std::invalid_argument for an object
  // without an element set.
  void step(Population& population, double t_start_s, double dt_s) override;
  bool takes_new_objects() const override { return false; }
  // The same at one instant t_s (for initial states).
  void set_states(Population& population, double t_s);

  // Objects that failed (other than by decay) at the last step.
  const std::vector<std::pair<ObjectId, Sgp4Error>>& failures() const { return failures_; }
  bool has(ObjectId id) const { return slot_of_.count(id) > 0; }

 private:
  void sync(const Population& population);

  std::unordered_map<ObjectId, std::size_t> slot_of_;
  std::vector<Sgp4Record> records_;   // by slot
  std::vector<double> offset_min_;    // by slot: minutes from the element epoch to the scenario epoch
  std::vector<ObjectId> synced_ids_;  // the population order the batch below was built for
  Sgp4Batch batch_;
  std::vector<double> batch_offset_min_, minutes_, x_, y_, z_, vx_, vy_, vz_;
  std::vector<Sgp4Error> errors_;
  std::vector<std::pair<ObjectId, Sgp4Error>> failures_;
};

}  // namespace kessler
