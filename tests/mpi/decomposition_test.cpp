// The arithmetic of the MPI decomposition (core/distributed/decomposition.hpp): the ranks' runs of
// objects cover every index once, in order, balanced; the gathers' counts; the rank-count check.
#include <gtest/gtest.h>

#include <limits>

#include "core/distributed/decomposition.hpp"

namespace kessler::distributed {
namespace {

TEST(Decomposition, RunsCoverEveryObjectOnceInRankOrderBalanced) {
  for (std::size_t n : {1u, 2u, 3u, 7u, 1000u, 1000003u}) {
    for (int ranks : {1, 2, 3, 4, 16}) {
      if (n < static_cast<std::size_t>(ranks)) continue;
      std::size_t next = 0, smallest = n, largest = 0;
      for (int r = 0; r < ranks; ++r) {
        const IndexRun run = run_of_rank(n, r, ranks);
        EXPECT_EQ(run.begin, next) << n << " objects, rank " << r << " of " << ranks;
        next = run.end;
        smallest = std::min(smallest, run.size());
        largest = std::max(largest, run.size());
      }
      EXPECT_EQ(next, n);
      EXPECT_LE(largest - smallest, 1u) << n << " objects over " << ranks << " ranks";
      EXPECT_GE(smallest, 1u);
    }
  }
}

TEST(Decomposition, GatherLayoutCountsInUnits) {
  const auto layout = gather_layout(10, 3, 8);
  ASSERT_TRUE(layout.has_value());
  EXPECT_EQ(layout->counts, (std::vector<int>{24, 24, 32}));  // 3, 3, 4 objects of 8 bytes
  EXPECT_EQ(layout->displacements, (std::vector<int>{0, 24, 48}));
  EXPECT_FALSE(gather_layout(std::size_t{1} << 30, 2, 8).has_value());  // 8 GiB: more than an int counts
}

TEST(Decomposition, RankCountMustFitThePopulation) {
  EXPECT_FALSE(check_rank_count(4, 4).has_value());
  EXPECT_FALSE(check_rank_count(1000000, 16).has_value());
  const auto too_many = check_rank_count(2, 4);
  ASSERT_TRUE(too_many.has_value());
  EXPECT_EQ(*too_many,
            "4 MPI ranks for 2 objects: every rank needs one object at least; run with at most 2 ranks");
  EXPECT_TRUE(check_rank_count(0, 1).has_value());
  EXPECT_TRUE(check_rank_count(static_cast<std::size_t>(std::numeric_limits<int>::max()) + 1, 2).has_value());
}

}  // namespace
}  // namespace kessler::distributed
