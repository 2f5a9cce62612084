// The MPI build: the session initialises MPI once per process (a process that already did, e.g. a
// test calling two commands, shares it) and finalises what it initialised.
#include <mpi.h>

#include <cstdlib>

#include "parallel_session.hpp"

namespace dynweigh::tools::grid {

ParallelSession::ParallelSession(bool join_mpi) {
  if (!join_mpi) return;
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (finalized) return;  // MPI cannot start twice in a process: stay a single process
  int initialized = 0;
  MPI_Initialized(&initialized);
  int provided = MPI_THREAD_FUNNELED;
  if (!initialized) {
    MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
    finalize_ = true;
  } else {
    MPI_Query_thread(&provided);
  }
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
  threads_beside_mpi_ = provided >= MPI_THREAD_FUNNELED;
}

ParallelSession::~ParallelSession() {
  if (finalize_) MPI_Finalize();
}

void ParallelSession::abort(int exit_code) const {
  if (size_ > 1) MPI_Abort(MPI_COMM_WORLD, exit_code);
  std::exit(exit_code);
}

}  // namespace dynweigh::tools::grid
