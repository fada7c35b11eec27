// How one run's work is shared out among MPI ranks: contiguous runs of object indices, balanced by count
// (propagation), and the grid's slots (detection, ConjunctionDetector::set_share). Plain arithmetic, no
// MPI, so it is tested on its own.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace kessler::distributed {

// Object indices [begin, end) that one rank propagates.
struct IndexRun {
  std::size_t begin = 0;
  std::size_t end = 0;
  std::size_t size() const { return end - begin; }
};

// Rank `rank` of `ranks`: objects [n rank / ranks, n (rank + 1) / ranks). The runs of all ranks cover
// [0, n) once, in rank order, and differ in size by at most one object.
IndexRun run_of_rank(std::size_t n, int rank, int ranks);

// Counts and displacements of every rank's run in units of `unit` (MPI_Allgatherv's arrays), or nullopt
// where one does not fit an int.
struct GatherLayout {
  std::vector<int> counts, displacements;
};
std::optional<GatherLayout> gather_layout(std::size_t n, int ranks, std::size_t unit = 1);

// Why a run of `objects` objects cannot be shared out among `ranks` ranks, or nullopt: every rank needs
// one object at least, and the gathers count in int.
std::optional<std::string> check_rank_count(std::size_t objects, int ranks);

}  // namespace kessler::distributed
