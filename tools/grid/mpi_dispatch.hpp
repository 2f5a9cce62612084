#pragma once
// The MPI back-end of the grid (built with DYNWEIGH_MPI). Rank 0 deals out jobs to whichever rank
// asks, keeping two in each rank's hand (so a rank starts its next job while its last row travels,
// and never waits on rank 0); a rank's finished row is its request for another. Rank 0 computes
// jobs too, on a thread of its own, while its main thread (the only one calling MPI) serves the
// others, so that N ranks on N cores keep N cores busy.
//
//   rank r -> 0: READY                      (once, at the start)
//   0 -> rank r: JOB "<job>" (up to two in hand)  or  STOP (nothing left, nothing in hand)
//   rank r -> 0: ROW "<job>\n<key>\n<row>"  (the key checks that every rank runs the same grid)
#include <cstddef>
#include <string>
#include <vector>

#include "local_workers.hpp"
#include "parallel_session.hpp"
#include "row_collector.hpp"

namespace dynweigh::tools::grid {

// Rank 0: until every job's row is in and every other rank has been told to stop.
void deal_out_jobs(const ParallelSession& session, const std::vector<std::string>& keys, JobQueue& queue,
                   const ComputeRow& compute, RowCollector& collector);

// Any other rank: computes what rank 0 deals out; returns how many jobs it computed.
std::size_t serve_jobs(const std::vector<std::string>& keys, const ComputeRow& compute);

}  // namespace dynweigh::tools::grid
