// The ranks of one run: the communicator, this rank's place in it, the seconds spent in MPI calls (the
// communication share a benchmark reports), and the rule that a failure on one rank fails every rank
// (else the others would wait forever in the next collective call).
#pragma once

#include <mpi.h>

#include <exception>
#include <functional>

namespace kessler::distributed {

class RankTeam {
 public:
  explicit RankTeam(MPI_Comm comm = MPI_COMM_WORLD);

  MPI_Comm comm() const { return comm_; }
  int rank() const { return rank_; }
  int ranks() const { return ranks_; }

  // Runs `work`; then, on every rank, throws if it threw on any rank: the rank's own exception where it
  // failed, else std::runtime_error naming the first rank that failed and its message. Collective.
  void all_or_none(const std::function<void()>& work);

  // Seconds spent in the MPI calls of the run's steps so far (timed by the callers through Timed).
  double mpi_s() const { return mpi_s_; }
  // Times one MPI call: adds its duration to mpi_s().
  class Timed {
   public:
    explicit Timed(RankTeam& team) : team_(team), start_(MPI_Wtime()) {}
    ~Timed() { team_.mpi_s_ += MPI_Wtime() - start_; }
    Timed(const Timed&) = delete;
    Timed& operator=(const Timed&) = delete;

   private:
    RankTeam& team_;
    double start_;
  };

 private:
  MPI_Comm comm_;
  int rank_ = 0;
  int ranks_ = 1;
  double mpi_s_ = 0.0;
};

}  // namespace kessler::distributed
