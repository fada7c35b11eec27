// Whether threads help walk each other's regions (core/parallel/walk_sharing.hpp): help stays on
// while helpers keep pace, goes off when they walk far slower than the owners, and is tried again now
// and then, so a machine whose cores exchange lines cheaply gets it back.
#include "core/parallel/walk_sharing.hpp"

#include <gtest/gtest.h>

#include <cstddef>

namespace kessler {
namespace {

// One scan's figures for a helper pace of `ratio` times the owners' (1000 slots a millisecond).
void record_pace(WalkSharing& sharing, double ratio) {
  sharing.record(100000, 0.1, 10000, 0.01 / ratio);
}

TEST(WalkSharing, HelpsWhileHelpersKeepPace) {
  WalkSharing sharing;
  EXPECT_TRUE(sharing.helping());  // no measurement yet: help, and measure
  for (int scan = 0; scan < 200; ++scan) {
    record_pace(sharing, 0.9);
    ASSERT_TRUE(sharing.helping()) << "scan " << scan;
  }
  EXPECT_NEAR(sharing.efficiency(), 0.9, 1e-6);
}

TEST(WalkSharing, StopsWhenHelpersAreSlowAndProbesNowAndThen) {
  WalkSharing sharing;
  int helped = 0;
  for (int scan = 0; scan < 40; ++scan) {
    if (sharing.helping()) ++helped;
    record_pace(sharing, 0.3);  // as measured far apart on this machine
  }
  EXPECT_LT(sharing.efficiency(), WalkSharing::kMinHelpEfficiency);
  EXPECT_LT(helped, 15);  // it stopped after a few scans
  // From then on, one scan in kProbeEvery helps.
  int probes = 0;
  const int scans = 10 * static_cast<int>(WalkSharing::kProbeEvery);
  for (int scan = 0; scan < scans; ++scan) {
    if (sharing.helping()) {
      ++probes;
      record_pace(sharing, 0.3);
    } else {
      sharing.record(100000, 0.1, 0, 0.0);  // no help, nothing measured
    }
  }
  EXPECT_EQ(probes, 10);
}

TEST(WalkSharing, ProbesTurnHelpBackOnWhenHelpersGetFaster) {
  WalkSharing sharing;
  for (int scan = 0; scan < 40; ++scan) record_pace(sharing, 0.2);
  ASSERT_LT(sharing.efficiency(), WalkSharing::kMinHelpEfficiency);
  int scan = 0;
  for (; scan < 100 * static_cast<int>(WalkSharing::kProbeEvery) &&
         sharing.efficiency() < WalkSharing::kMinHelpEfficiency;
       ++scan) {
    if (sharing.helping())
      record_pace(sharing, 1.0);  // the host moved the threads onto cores that share a cache
    else
      sharing.record(100000, 0.1, 0, 0.0);
  }
  EXPECT_GE(sharing.efficiency(), WalkSharing::kMinHelpEfficiency);
  EXPECT_TRUE(sharing.helping());
}

// A scan with (almost) no help, or no own walk, measures nothing.
TEST(WalkSharing, ScansWithoutHelpMeasureNothing) {
  WalkSharing sharing;
  sharing.record(100000, 0.1, 10, 1.0);
  sharing.record(0, 0.0, 10000, 0.01);
  EXPECT_EQ(sharing.efficiency(), 1.0);
}

}  // namespace
}  // namespace kessler
