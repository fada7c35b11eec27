// kessler-mpi on a scenario with `ensemble: {members: N}`: the members spread over groups of ranks
// (MPI_Comm_split), each member whole on one group, member k with the seed base + k as kesslerd's
// ensembles give it (server/ensembles.cpp); each group runs its members one after the other, and world
// rank 0 prints one summary line per member in member order.
#pragma once

#include <functional>
#include <string>

#include "client/commands/local_run.hpp"
#include "core/distributed/rank_team.hpp"

namespace kessler::cli {

struct EnsembleOptions {
  int ranks_per_member = 0;  // 0: ranks / members rounded down, at least 1
  bool json = false;
};

// Runs one member (`run` names its scenario) on `team`, printing nothing: returns its exit code.
using RunMember = std::function<int(LocalRunOptions& run, distributed::RankTeam& team)>;

// Collective over `world`. `scenario`: the ensemble's scenario, read and valid. Returns the exit code:
// 0 when every member finished, 1 when one failed, 2 for a bad --ranks-per-member (on every rank).
int run_ensemble(const LocalRunOptions& base, const v1::Scenario& scenario, const EnsembleOptions& options,
                 distributed::RankTeam& world, const RunMember& run_member);

}  // namespace kessler::cli
