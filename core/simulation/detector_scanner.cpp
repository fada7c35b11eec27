// ConjunctionDetector behind the EncounterScanner interface the loop reads.
#include "core/conjunctions/detector.hpp"
#include "core/simulation/simulation_parts.hpp"

namespace kessler {
namespace {

class DetectorScanner final : public EncounterScanner {
 public:
  explicit DetectorScanner(const ConjunctionSettings& settings) : settings_(settings), detector_(settings) {}
  void scan(const Population& population, const StepEnds& step, std::vector<Encounter>& out) override {
    detector_.scan(population, step, out);
  }
  double last_grid_s() const override { return detector_.last_grid_s(); }
  std::unique_ptr<EncounterScanner> another() const override {
    return std::make_unique<DetectorScanner>(settings_);
  }

 private:
  ConjunctionSettings settings_;
  ConjunctionDetector detector_;
};

}  // namespace

std::unique_ptr<EncounterScanner> make_detector_scanner(const ConjunctionSettings& settings) {
  return std::make_unique<DetectorScanner>(settings);
}

}  // namespace kessler
