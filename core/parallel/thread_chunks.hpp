// How a step's objects are shared between the threads of a team: one contiguous chunk each, objects
// [n t / team, n (t + 1) / team). The propagator, the burn-up test and the detector's grid all split
// this way (the grid moves the borders by its threads' measured costs: BroadPhaseGrid::pass_chunk), so
// each core reads back the states it wrote itself: a line another core wrote costs several times more
// to read, and writing a line another core has read costs more still.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <memory>
#include <vector>

namespace kessler {

// Below this many objects a step runs on a team of one: more threads cost more than they save.
inline constexpr std::size_t kPropagationParallelMinimum = 512;

struct ThreadChunk {
  std::size_t begin, end;  // population indices [begin, end)
};

// Chunks start at multiples of kChunkAlign objects: the loops over a chunk are vectorised 8 doubles wide,
// and a chunk (or block) that starts or ends between two vectors runs its first or last few objects in
// scalar code, several times dearer per object.
inline constexpr std::size_t kChunkAlign = 8;

inline ThreadChunk thread_chunk(std::size_t n, std::size_t thread, std::size_t team) {
  auto boundary = [&](std::size_t k) { return k == team ? n : n * k / team / kChunkAlign * kChunkAlign; };
  return {boundary(thread), boundary(thread + 1)};
}

// Chunks of equal cost rather than equal size: some objects cost a step more than others (the
// propagator's low objects take four sub-steps), and they cluster in a catalog (one launch's or one
// breakup's decaying objects sit together). With chunks of equal size, the team evened that out by stealing
// blocks, whose lines then moved between cores twice (the thief's writes, then the owner's box pass), and the
// threads still finished up to a block apart. The layout is the propagator's, handed to the grid's box pass
// through StepEnds so that each thread still reads the states its own core wrote. Only which core handles an
// object depends on it, never a result.
class ChunkLayout {
 public:
  // Equal chunks (thread_chunk) of n objects for `team` threads.
  void even(std::size_t n, std::size_t team) {
    starts_.resize(team + 1);
    for (std::size_t t = 0; t < team; ++t) starts_[t] = thread_chunk(n, t, team).begin;
    starts_[team] = n;
  }
  // Chunks of equal cost when each object costs 1 and each of `costly` (population indices, ascending;
  // any beyond n are ignored) costs 1 + extra_cost; each start on a vector boundary.
  template <typename Index>
  void weighted(std::size_t n, std::size_t team, const std::vector<Index>& costly, double extra_cost) {
    std::size_t heavy = 0;
    while (heavy < costly.size() && static_cast<std::size_t>(costly[heavy]) < n) ++heavy;
    if (heavy == 0 || team < 2) return even(n, team);
    starts_.resize(team + 1);
    starts_[0] = 0;
    starts_[team] = n;
    const double total = static_cast<double>(n) + extra_cost * static_cast<double>(heavy);
    // The cost of objects [0, i) is i plus extra_cost for each costly one below i: walk both in order.
    std::size_t below = 0;  // costly objects below the current start
    for (std::size_t t = 1; t < team; ++t) {
      const double target = total * static_cast<double>(t) / static_cast<double>(team);
      // Where the prefix cost reaches the target if `below` costly objects lie under it; each costly
      // object found under that start moves it down by extra_cost.
      auto start_with = [&](std::size_t costly_below) {
        const double ordinary = target - extra_cost * static_cast<double>(costly_below);
        return ordinary <= 0.0 ? std::size_t{0} : static_cast<std::size_t>(ordinary);
      };
      std::size_t i = start_with(below);
      while (below < heavy && static_cast<std::size_t>(costly[below]) < i) i = start_with(++below);
      i = std::min(i, n) / kChunkAlign * kChunkAlign;
      starts_[t] = std::max(starts_[t - 1], i);
    }
  }
  std::size_t team() const { return starts_.empty() ? 0 : starts_.size() - 1; }
  std::size_t objects() const { return starts_.empty() ? 0 : starts_.back(); }
  ThreadChunk chunk(std::size_t thread) const { return {starts_[thread], starts_[thread + 1]}; }

 private:
  std::vector<std::size_t> starts_;  // team + 1 entries: chunk t is [starts_[t], starts_[t + 1])
};

// Thread t's chunk: the layout's, when it was made for this team and these n objects, else equal ones.
inline ThreadChunk thread_chunk(const ChunkLayout* layout, std::size_t n, std::size_t thread,
                                std::size_t team) {
  if (layout != nullptr && layout->team() == team && layout->objects() == n) return layout->chunk(thread);
  return thread_chunk(n, thread, team);
}

// The blocks of a team's chunks, handed out with stealing: each thread takes the blocks of its own chunk
// first, in order, then what is left of the other chunks (from the next thread's on). A core that runs
// slow for a while, or a chunk that holds costly objects, no longer holds up the team at the next
// barrier, and most objects are still handled on the core that holds their lines. Which thread takes a
// block changes no result where each object's arithmetic depends on that object alone.
class ChunkBlocks {
 public:
  // Before the region (one thread): the chunks of `layout`, one per thread of its team, in blocks of
  // `block` (rounded up to a multiple of kChunkAlign, so that blocks start on a vector boundary too).
  void reset(const ChunkLayout& layout, std::size_t block) {
    const std::size_t team = layout.team();
    block = (block + kChunkAlign - 1) / kChunkAlign * kChunkAlign;
    if (team > capacity_) {
      cursors_ = std::make_unique<Cursor[]>(team);
      capacity_ = team;
    }
    team_ = team;
    block_ = block;
    for (std::size_t t = 0; t < team; ++t) {
      const ThreadChunk chunk = layout.chunk(t);
      cursors_[t].next.store(chunk.begin, std::memory_order_relaxed);
      cursors_[t].end = chunk.end;
    }
  }
  // Inside the region: thread t's blocks, one at a time. Every block is taken once, also when OpenMP
  // gives the region fewer threads than `team`.
  class Claimer {
   public:
    Claimer(ChunkBlocks& blocks, std::size_t thread) : blocks_(&blocks), thread_(thread) {}
    // The next block [begin, end) for this thread; false when every block is taken.
    bool next(std::size_t& begin, std::size_t& end) {
      const std::size_t team = blocks_->team_;
      for (; visited_ < team; ++visited_) {
        Cursor& chunk = blocks_->cursors_[(thread_ + visited_) % team];
        // Read before claiming: a chunk already done costs no write to its line.
        if (chunk.next.load(std::memory_order_relaxed) >= chunk.end) continue;
        const std::size_t claimed = chunk.next.fetch_add(blocks_->block_, std::memory_order_relaxed);
        if (claimed >= chunk.end) continue;
        begin = claimed;
        end = claimed + blocks_->block_ < chunk.end ? claimed + blocks_->block_ : chunk.end;
        return true;
      }
      return false;
    }

   private:
    ChunkBlocks* blocks_;
    std::size_t thread_, visited_ = 0;  // chunks looked at so far, from the thread's own on
  };
  Claimer claimer(std::size_t thread) { return Claimer(*this, thread); }

 private:
  struct alignas(64) Cursor {  // each on its own line: its owner claims from it without sharing
    std::atomic<std::size_t> next{0};
    std::size_t end = 0;
  };
  std::unique_ptr<Cursor[]> cursors_;
  std::size_t capacity_ = 0, team_ = 0, block_ = 1;
};

}  // namespace kessler
