// How a step's objects are shared between the threads of a team: one contiguous chunk each, objects
// [n t / team, n (t + 1) / team). The propagator, the burn-up test and the detector's grid all split
// this way, so each core reads back the states it wrote itself: a line another core wrote costs several
// times more to read, and writing a line another core has read costs more still.
#pragma once

#include <cstddef>
#include <cstring>

namespace kessler {

// Below this many objects a step runs on a team of one: more threads cost more than they save.
inline constexpr std::size_t kPropagationParallelMinimum = 512;

struct ThreadChunk {
  std::size_t begin, end;  // population indices [begin, end)
};

inline ThreadChunk thread_chunk(std::size_t n, std::size_t thread, std::size_t team) {
  return {n * thread / team, n * (thread + 1) / team};
}

// Calls f(i) for each i in [begin, end) whose flag is 1, in order. Flags set are rare (burn-ups, low
// objects), so it jumps from one to the next with memchr.
template <class F>
void for_each_flagged(const char* flags, std::size_t begin, std::size_t end, F&& f) {
  for (const char* p = flags + begin; p < flags + end; ++p) {
    p = static_cast<const char*>(std::memchr(p, 1, static_cast<std::size_t>(flags + end - p)));
    if (p == nullptr) return;
    f(static_cast<std::size_t>(p - flags));
  }
}

}  // namespace kessler
