#include "client/mpi/mpi_ensemble.hpp"

#include <mpi.h>

#include <algorithm>
#include <iostream>
#include <sstream>
#include <vector>

namespace kessler::cli {
namespace {

constexpr int kResultTag = 47;

std::string member_line(std::uint64_t member, std::uint64_t seed, int exit, const RunSummary& s, bool json) {
  std::ostringstream line;
  const char* state = exit == kExitOk ? "succeeded" : "failed";
  if (json) {
    line << "{\"type\":\"member\",\"member\":" << member << ",\"seed\":" << seed << ",\"state\":\"" << state
         << "\",\"steps\":" << s.steps << ",\"events\":" << s.events << ",\"conjunctions\":" << s.conjunctions
         << ",\"collisions\":" << s.collisions << ",\"objects_final\":" << s.objects_final
         << ",\"events_digest\":\"" << s.events_digest << "\",\"state_digest\":\"" << s.state_digest << "\"}";
  } else {
    line << "member " << member << "  seed " << seed << "  " << state << "  events " << s.events
         << "  conjunctions " << s.conjunctions << "  events_digest " << s.events_digest << "  state_digest "
         << s.state_digest;
  }
  return line.str();
}

// The members' lines, in member order, from the group leaders to world rank 0 (which prints them); the
// worst exit code on every rank.
int report(const std::vector<std::string>& my_lines, std::uint64_t members, int groups, int ranks_per_member,
           int my_exit, distributed::RankTeam& world) {
  const bool leader = world.rank() % ranks_per_member == 0 && world.rank() < groups * ranks_per_member;
  std::vector<MPI_Request> sends;
  if (leader && world.rank() != 0)
    for (std::size_t i = 0; i < my_lines.size(); ++i) {
      sends.emplace_back();
      MPI_Isend(my_lines[i].data(), static_cast<int>(my_lines[i].size()), MPI_CHAR, 0, kResultTag,
                world.comm(), &sends.back());
    }
  if (world.rank() == 0) {
    std::size_t mine = 0;
    for (std::uint64_t m = 0; m < members; ++m) {
      const int source = static_cast<int>(m % static_cast<std::uint64_t>(groups)) * ranks_per_member;
      if (source == 0) {
        std::cout << my_lines[mine++] << '\n';
        continue;
      }
      MPI_Status status;
      // One tag: messages of one source arrive in the order sent, its members' order.
      MPI_Probe(source, kResultTag, world.comm(), &status);
      int size = 0;
      MPI_Get_count(&status, MPI_CHAR, &size);
      std::string line(static_cast<std::size_t>(size), '\0');
      MPI_Recv(line.data(), size, MPI_CHAR, source, kResultTag, world.comm(), MPI_STATUS_IGNORE);
      std::cout << line << '\n';
    }
    std::cout.flush();
  }
  MPI_Waitall(static_cast<int>(sends.size()), sends.data(), MPI_STATUSES_IGNORE);
  int worst = my_exit;
  MPI_Allreduce(MPI_IN_PLACE, &worst, 1, MPI_INT, MPI_MAX, world.comm());
  return worst;
}

}  // namespace

int run_ensemble(const LocalRunOptions& base, const v1::Scenario& scenario, const EnsembleOptions& options,
                 distributed::RankTeam& world, const RunMember& run_member) {
  const std::uint64_t members = std::max<std::uint64_t>(scenario.ensemble().members(), 1);
  const int ranks = world.ranks();
  int per_member = options.ranks_per_member;
  if (per_member == 0)
    per_member = static_cast<int>(std::max<std::uint64_t>(static_cast<std::uint64_t>(ranks) / members, 1));
  if (per_member > ranks) {
    std::cerr << base.program << ": --ranks-per-member " << per_member << " is more than the job's " << ranks
              << " ranks\n";
    return kExitUsage;
  }
  const int groups = ranks / per_member;  // ranks past groups * per_member stay idle
  const int group = world.rank() < groups * per_member ? world.rank() / per_member : MPI_UNDEFINED;
  MPI_Comm group_comm = MPI_COMM_NULL;
  MPI_Comm_split(world.comm(), group, world.rank(), &group_comm);

  v1::Scenario member_scenario = scenario;
  member_scenario.clear_ensemble();
  const std::uint64_t base_seed = scenario.has_seed() ? scenario.seed() : 1;  // the core's default seed
  std::vector<std::string> lines;
  int worst = kExitOk;
  if (group_comm != MPI_COMM_NULL) {
    distributed::RankTeam team(group_comm);
    for (std::uint64_t m = static_cast<std::uint64_t>(group); m < members;
         m += static_cast<std::uint64_t>(groups)) {
      member_scenario.set_seed(base_seed + m);
      NullSink sink;
      RunSummary summary;
      LocalRunOptions run = base;
      run.scenario = &member_scenario;
      run.sink = &sink;
      run.on_summary = [&](const RunSummary& s) { summary = s; };
      const int exit = run_member(run, team);
      worst = std::max(worst, exit);
      lines.push_back(member_line(m, base_seed + m, exit, summary, options.json));
    }
  }
  const int exit = report(lines, members, groups, per_member, worst, world);
  if (group_comm != MPI_COMM_NULL) MPI_Comm_free(&group_comm);
  return exit;
}

}  // namespace kessler::cli
