#include "core/distributed/rank_team.hpp"

#include <stdexcept>
#include <string>
#include <vector>

namespace kessler::distributed {

RankTeam::RankTeam(MPI_Comm comm) : comm_(comm) {
  MPI_Comm_rank(comm_, &rank_);
  MPI_Comm_size(comm_, &ranks_);
}

void RankTeam::all_or_none(const std::function<void()>& work) {
  std::exception_ptr failure;
  std::string message;
  try {
    work();
  } catch (const std::exception& e) {
    failure = std::current_exception();
    message = e.what();
  } catch (...) {
    failure = std::current_exception();
    message = "unknown error";
  }
  // The lowest failing rank (ranks_ where none failed), then its message to every rank.
  int first_failed = failure ? rank_ : ranks_;
  {
    Timed timed(*this);
    MPI_Allreduce(MPI_IN_PLACE, &first_failed, 1, MPI_INT, MPI_MIN, comm_);
  }
  if (first_failed == ranks_) return;
  // Every rank takes part in the broadcast, the failed ones too, before any throws.
  int length = static_cast<int>(message.size());
  MPI_Bcast(&length, 1, MPI_INT, first_failed, comm_);
  std::vector<char> text(message.begin(), message.end());
  text.resize(static_cast<std::size_t>(length));
  MPI_Bcast(text.data(), length, MPI_CHAR, first_failed, comm_);
  if (failure) std::rethrow_exception(failure);
  throw std::runtime_error("MPI rank " + std::to_string(first_failed) + ": " +
                           std::string(text.begin(), text.end()));
}

}  // namespace kessler::distributed
