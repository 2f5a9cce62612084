// The plain build: one process; joining "MPI" joins a job of one rank.
#include <cstdlib>

#include "parallel_session.hpp"

namespace dynweigh::tools::grid {

ParallelSession::ParallelSession(bool) {}

ParallelSession::~ParallelSession() = default;

void ParallelSession::abort(int exit_code) const { std::exit(exit_code); }

}  // namespace dynweigh::tools::grid
