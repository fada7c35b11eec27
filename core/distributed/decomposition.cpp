#include "core/distributed/decomposition.hpp"

#include <limits>

namespace kessler::distributed {

IndexRun run_of_rank(std::size_t n, int rank, int ranks) {
  const auto r = static_cast<std::size_t>(rank), parts = static_cast<std::size_t>(ranks);
  return {n * r / parts, n * (r + 1) / parts};
}

std::optional<GatherLayout> gather_layout(std::size_t n, int ranks, std::size_t unit) {
  constexpr auto kMaxInt = static_cast<std::size_t>(std::numeric_limits<int>::max());
  if (n > kMaxInt / unit) return std::nullopt;
  GatherLayout layout;
  layout.counts.resize(static_cast<std::size_t>(ranks));
  layout.displacements.resize(static_cast<std::size_t>(ranks));
  for (int r = 0; r < ranks; ++r) {
    const IndexRun run = run_of_rank(n, r, ranks);
    layout.counts[static_cast<std::size_t>(r)] = static_cast<int>(run.size() * unit);
    layout.displacements[static_cast<std::size_t>(r)] = static_cast<int>(run.begin * unit);
  }
  return layout;
}

std::optional<std::string> check_rank_count(std::size_t objects, int ranks) {
  if (ranks < 1) return "the rank count must be at least 1, got " + std::to_string(ranks);
  if (objects < static_cast<std::size_t>(ranks))
    return std::to_string(ranks) + " MPI ranks for " + std::to_string(objects) +
           " objects: every rank needs one object at least; run with at most " + std::to_string(objects) +
           " ranks";
  if (objects > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    return std::to_string(objects) + " objects: more than an MPI gather counts (2^31 - 1)";
  return std::nullopt;
}

}  // namespace kessler::distributed
