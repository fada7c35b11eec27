#include "core/distributed/distributed_scanner.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace kessler::distributed {

// Encounters travel as bytes between ranks of one build: plain values with no pointers (ids, doubles, and
// Eigen's fixed-size vectors, which hold their three doubles in place; Eigen declares a copy constructor,
// so the type is not formally trivially copyable).
static_assert(std::is_standard_layout_v<Eigen::Vector3d> && sizeof(Eigen::Vector3d) == 3 * sizeof(double),
              "Encounter must travel as bytes");

DistributedScanner::DistributedScanner(const ConjunctionSettings& settings, RankTeam& team)
    : team_(team), detector_(settings) {
  detector_.set_share(static_cast<std::size_t>(team_.rank()), static_cast<std::size_t>(team_.ranks()));
}

void DistributedScanner::scan(const Population& population, const StepEnds& step,
                              std::vector<Encounter>& out) {
  mine_.clear();
  team_.all_or_none([&] {
    const double start = MPI_Wtime();
    detector_.scan(population, step, mine_);
    compute_s_ += MPI_Wtime() - start;
    if (mine_.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()) / sizeof(Encounter))
      throw std::runtime_error("more encounters in one step than an MPI gather holds");
  });
  const auto ranks = static_cast<std::size_t>(team_.ranks());
  bytes_of_rank_.resize(ranks);
  displacements_.resize(ranks);
  int my_bytes = static_cast<int>(mine_.size() * sizeof(Encounter));
  // Each rank's byte count, with the grid it walked a share of: the shares cover every slot once only
  // if all ranks laid out the same grid (the same slot count, on teams of the same size). And the cells
  // it sorted that hold objects: their sum is what every rank's next grid coarsens by, alike.
  constexpr std::size_t kShape = 4;
  const long long mine[kShape] = {my_bytes, static_cast<long long>(detector_.grid().slot_count()),
                                  static_cast<long long>(detector_.last_team_size()),
                                  static_cast<long long>(detector_.sorted_occupied_cells())};
  shapes_.resize(kShape * ranks);
  {
    RankTeam::Timed timed(team_);
    MPI_Allgather(mine, kShape, MPI_LONG_LONG, shapes_.data(), kShape, MPI_LONG_LONG, team_.comm());
  }
  std::size_t occupied_cells = 0;
  for (std::size_t r = 0; r < ranks; ++r) {
    const long long* shape = &shapes_[kShape * r];
    bytes_of_rank_[r] = static_cast<int>(shape[0]);
    occupied_cells += static_cast<std::size_t>(shape[3]);
    if (population.size() >= 2 && (shape[1] != mine[1] || shape[2] != mine[2]))
      throw std::runtime_error(
          "MPI rank " + std::to_string(r) + " laid out another grid (" + std::to_string(shape[1]) +
          " slots on " + std::to_string(shape[2]) + " threads, here " + std::to_string(mine[1]) + " on " +
          std::to_string(mine[2]) + "): every rank must scan on the same number of threads (--threads)");
  }
  detector_.set_all_parts_occupied(occupied_cells);
  std::size_t total_bytes = 0;
  for (std::size_t r = 0; r < ranks; ++r) {
    if (total_bytes > static_cast<std::size_t>(std::numeric_limits<int>::max()))
      throw std::runtime_error("more encounters in one step than an MPI gather holds");
    displacements_[r] = static_cast<int>(total_bytes);
    total_bytes += static_cast<std::size_t>(bytes_of_rank_[r]);
  }
  const std::size_t first = out.size();
  out.resize(first + total_bytes / sizeof(Encounter));
  {
    RankTeam::Timed timed(team_);
    MPI_Allgatherv(mine_.data(), my_bytes, MPI_BYTE, out.data() + first, bytes_of_rank_.data(),
                   displacements_.data(), MPI_BYTE, team_.comm());
  }
  // Each rank's list is sorted already; the whole, in the detector's canonical order.
  std::sort(out.begin() + static_cast<std::ptrdiff_t>(first), out.end(), canonical_less);
}

}  // namespace kessler::distributed
