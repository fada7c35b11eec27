// How a step's objects are shared out between threads (core/parallel/thread_chunks.hpp): every object
// is taken exactly once, whatever the team, the block size, or the number of threads OpenMP really gives.
#include <gtest/gtest.h>
#include <omp.h>

#include <cstdint>
#include <vector>

#include "core/parallel/thread_chunks.hpp"

namespace kessler {
namespace {

// Runs ChunkBlocks for `team` chunks with `running` threads and counts how often each object is taken;
// also counts the blocks each thread took from its own chunk.
std::vector<int> times_taken(std::size_t n, std::size_t team, std::size_t block, int running,
                             std::vector<std::size_t>* own_blocks = nullptr) {
  ChunkLayout equal;
  equal.even(n, team);
  ChunkBlocks blocks;
  blocks.reset(equal, block);
  std::vector<int> taken(n, 0);
  std::vector<std::size_t> own(team, 0);
#pragma omp parallel num_threads(running)
  {
    const std::size_t t = static_cast<std::size_t>(omp_get_thread_num());
    ChunkBlocks::Claimer claims = blocks.claimer(t);
    for (std::size_t begin = 0, end = 0; claims.next(begin, end);) {
      EXPECT_LT(begin, end);
      // Blocks are rounded up to whole vectors and start on one, so no loop over a block has a scalar
      // head (only the population's last block may end between two vectors).
      EXPECT_LE(end - begin, (block + kChunkAlign - 1) / kChunkAlign * kChunkAlign);
      EXPECT_EQ(begin % kChunkAlign, 0u);
      const ThreadChunk mine = thread_chunk(n, t, team);
      if (t < team && begin >= mine.begin && end <= mine.end) {
#pragma omp atomic
        ++own[t];
      }
      for (std::size_t i = begin; i < end; ++i) {
#pragma omp atomic
        ++taken[i];
      }
    }
  }
  if (own_blocks) *own_blocks = own;
  return taken;
}

TEST(ChunkBlocks, EveryObjectIsTakenOnce) {
  for (std::size_t n : {1u, 5u, 127u, 128u, 129u, 1000u, 19647u})
    for (std::size_t team : {1u, 2u, 3u, 16u})
      for (std::size_t block : {1u, 7u, 128u}) {
        const std::vector<int> taken = times_taken(n, team, block, static_cast<int>(team));
        for (std::size_t i = 0; i < n; ++i)
          ASSERT_EQ(taken[i], 1) << "object " << i << " of " << n << ", team " << team << ", block " << block;
      }
}

// The chunks tile the population in order and start on a vector boundary.
TEST(ThreadChunk, ChunksTileThePopulationOnVectorBoundaries) {
  for (std::size_t n : {0u, 7u, 512u, 19647u, 320000u})
    for (std::size_t team : {1u, 2u, 3u, 16u, 64u}) {
      std::size_t expected_begin = 0;
      for (std::size_t t = 0; t < team; ++t) {
        const ThreadChunk chunk = thread_chunk(n, t, team);
        EXPECT_EQ(chunk.begin, expected_begin);
        EXPECT_LE(chunk.begin, chunk.end);
        EXPECT_EQ(chunk.begin % kChunkAlign, 0u);
        expected_begin = chunk.end;
      }
      EXPECT_EQ(expected_begin, n);
    }
}

// Chunks of equal cost: they tile the population in order on vector boundaries, each costs its share of
// the total to within a vector and one object (of costly ones) at each end, and costly objects beyond the
// population (indices from before a burn-up) are ignored.
TEST(ChunkLayout, WeightedChunksCostTheSameAndTileThePopulation) {
  const std::size_t n = 19647;
  const double extra = 3.5;
  std::vector<std::uint32_t> costly;
  for (std::uint32_t i = 17000; i < 17400; ++i) costly.push_back(i);  // clustered, as in a catalog
  costly.push_back(30000);                                            // beyond the population
  for (std::size_t team : {2u, 3u, 16u}) {
    ChunkLayout layout;
    layout.weighted(n, team, costly, extra);
    ASSERT_EQ(layout.team(), team);
    ASSERT_EQ(layout.objects(), n);
    const double total = static_cast<double>(n) + extra * 400.0;
    // Each end of a chunk is rounded down to a vector, and may stop one object short: in the cluster
    // of costly objects, that many costly ones.
    const double bound = 2.0 * static_cast<double>(kChunkAlign + 1) * (1.0 + extra);
    std::size_t expected_begin = 0;
    for (std::size_t t = 0; t < team; ++t) {
      const ThreadChunk chunk = layout.chunk(t);
      EXPECT_EQ(chunk.begin, expected_begin);
      EXPECT_EQ(chunk.begin % kChunkAlign, 0u);
      double cost = static_cast<double>(chunk.end - chunk.begin);
      for (std::uint32_t i : costly)
        if (i >= chunk.begin && i < chunk.end) cost += extra;
      EXPECT_NEAR(cost, total / static_cast<double>(team), bound) << "team " << team << ", chunk " << t;
      expected_begin = chunk.end;
    }
    EXPECT_EQ(expected_begin, n);
  }
  // Without costly objects (or with one thread): equal chunks.
  ChunkLayout plain;
  plain.weighted(n, 3, std::vector<std::uint32_t>{}, extra);
  for (std::size_t t = 0; t < 3; ++t) {
    EXPECT_EQ(plain.chunk(t).begin, thread_chunk(n, t, 3).begin);
    EXPECT_EQ(plain.chunk(t).end, thread_chunk(n, t, 3).end);
  }
  // A layout for another team or population size is not used.
  EXPECT_EQ(thread_chunk(&plain, n, 1, 2).begin, thread_chunk(n, 1, 2).begin);
  EXPECT_EQ(thread_chunk(&plain, n - 8, 1, 3).begin, thread_chunk(n - 8, 1, 3).begin);
}

// Blocks handed out from unequal chunks still take every object once, each thread its own chunk first.
TEST(ChunkBlocks, UnequalChunksAreTakenWhole) {
  std::vector<std::uint32_t> costly;
  for (std::uint32_t i = 0; i < 600; ++i) costly.push_back(i);
  ChunkLayout layout;
  layout.weighted(4000, 4, costly, 9.0);
  ASSERT_LT(layout.chunk(0).end, 1000u);  // the costly objects' chunk is the smallest
  ChunkBlocks blocks;
  blocks.reset(layout, 64);
  std::vector<int> taken(4000, 0);
  for (std::size_t t = 0; t < 4; ++t) {  // one thread after another: each takes its own chunk first
    ChunkBlocks::Claimer claims = blocks.claimer(t);
    std::size_t begin = 0, end = 0;
    if (t == 0) {
      ASSERT_TRUE(claims.next(begin, end));
      EXPECT_EQ(begin, layout.chunk(0).begin);
      for (std::size_t i = begin; i < end; ++i) ++taken[i];
    }
    while (claims.next(begin, end))
      for (std::size_t i = begin; i < end; ++i) ++taken[i];
  }
  for (std::size_t i = 0; i < taken.size(); ++i) ASSERT_EQ(taken[i], 1) << "object " << i;
}

// OpenMP may give a region fewer threads than asked for: the chunks of the missing threads must still
// be taken by the others.
TEST(ChunkBlocks, FewerThreadsThanChunksStillTakeEverything) {
  for (int running : {1, 2, 3}) {
    const std::vector<int> taken = times_taken(5000, 8, 64, running);
    for (std::size_t i = 0; i < taken.size(); ++i) ASSERT_EQ(taken[i], 1) << "object " << i;
  }
}

// A thread starts with its own chunk: alone, it takes all of its own blocks (and then the others').
TEST(ChunkBlocks, OneThreadTakesItsOwnChunkFirst) {
  std::vector<std::size_t> own;
  times_taken(1000, 4, 50, 1, &own);
  EXPECT_EQ(own[0], 5u);  // objects 0..249 in blocks of 50
}

}  // namespace
}  // namespace kessler
