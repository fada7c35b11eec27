// How a step's objects are shared out between threads (core/integration/thread_chunks.hpp): every object
// is taken exactly once, whatever the team, the block size, or the number of threads OpenMP really gives.
#include <gtest/gtest.h>
#include <omp.h>

#include <vector>

#include "core/integration/thread_chunks.hpp"

namespace kessler {
namespace {

// Runs ChunkBlocks for `team` chunks with `running` threads and counts how often each object is taken;
// also counts the blocks each thread took from its own chunk.
std::vector<int> times_taken(std::size_t n, std::size_t team, std::size_t block, int running,
                             std::vector<std::size_t>* own_blocks = nullptr) {
  ChunkBlocks blocks;
  blocks.reset(n, team, block);
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
