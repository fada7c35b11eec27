// Whether threads that are done walking their own region of the grid help walk the others'.
//
// A helper walks slots another core has just sorted: it reads that core's slot arrays and bucket table
// (lines that must cross between the cores), and the owner's next sort must take those lines back
// before writing them. Where lines cross cheaply, helping evens out the threads' ends. Where they do
// not (cores far apart), it costs more than it saves. So the team measures it: each scan times the
// slots walked by their owner and by helpers, and help stays on while a helper walks at least
// kMinHelpEfficiency of its owner's pace (smoothed over scans). While off, one scan in kProbeEvery helps
// anyway, to measure again. Who walks which slots never changes a result, only when the team is done.
#pragma once

#include <cstddef>

namespace kessler {

class WalkSharing {
 public:
  // Helping pays while a helper walks at least this share of its owner's slots per second (it pays back
  // the owner's dearer next sort only at about this pace).
  static constexpr double kMinHelpEfficiency = 0.6;
  // While help is off, every kProbeEvery-th scan helps, to measure the pace again.
  static constexpr std::size_t kProbeEvery = 32;
  // Weight of one scan's pace ratio in the smoothed one.
  static constexpr double kSmoothing = 0.125;

  // Whether this scan's threads help each other.
  bool helping() const { return efficiency_ >= kMinHelpEfficiency || scans_ % kProbeEvery == 0; }

  // After a scan: slots walked by their owners and by helpers, and the seconds they took (summed over
  // the threads). A scan with too little of either says nothing.
  void record(std::size_t own_slots, double own_s, std::size_t helped_slots, double helped_s) {
    ++scans_;
    constexpr std::size_t kMinSlots = 64;
    if (own_slots < kMinSlots || helped_slots < kMinSlots || !(own_s > 0.0) || !(helped_s > 0.0)) return;
    const double ratio =
        (static_cast<double>(helped_slots) / helped_s) / (static_cast<double>(own_slots) / own_s);
    efficiency_ += kSmoothing * (ratio - efficiency_);
  }

  // The smoothed pace of helpers over owners (1 before any measurement: help, and measure).
  double efficiency() const { return efficiency_; }

 private:
  double efficiency_ = 1.0;
  std::size_t scans_ = 0;
};

}  // namespace kessler
