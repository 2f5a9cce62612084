#pragma once
// A grid of independent jobs (a bench's series, a calibration's parameter points): each job has a
// stable key and a function computes its result row (one line of text). The rows come back in the
// jobs' order whatever ran them: the threads of one process, or the ranks of an MPI job. A row must
// depend only on its job (seeds from the key or the seed index, never from a rank or a thread), so
// the output is the same bytes however the grid was split, and whether or not it was resumed.
//
//   grid::ParallelSession session(true);
//   grid::GridOptions options;
//   options.threads = jobs; options.journal_path = "bench.csv.journal"; options.resume = resume;
//   options.signature = "bench seeds=50";
//   const grid::GridOutcome out = grid::run_grid(session, keys, [&](std::size_t i) { return row(i); }, options);
//   if (session.writer()) for (const auto& row : out.rows) print(row);
//
// With MPI and more than one rank, rank 0 deals the jobs out in the grid's order to whichever rank
// asks, two in each rank's hand (a dynamic work queue: bench series differ tenfold in cost, so a
// static split would leave ranks idle), computes jobs itself on a second thread, journals each row
// as it arrives and alone holds the rows at the end. Each rank computes one job at a time;
// `threads` applies to a single process.
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "local_workers.hpp"
#include "parallel_session.hpp"

namespace dynweigh::tools::grid {

struct GridOptions {
  unsigned threads = 1;       // worker threads of a single process
  std::string journal_path;   // empty: no journal
  bool resume = false;        // take the journal's intact rows, compute only the missing jobs
  std::string signature;      // what decides a row besides its key (written in the journal, checked on resume)
  std::function<void(std::size_t finished, std::size_t total)> progress;  // on the writer
};

struct GridOutcome {
  std::vector<std::string> rows;  // in the jobs' order, on the writer; empty on other ranks
  std::size_t computed = 0;       // rows computed by this run (on the writer: by every rank)
  std::size_t skipped = 0;        // rows the journal already held
  std::vector<std::size_t> computed_by_rank;  // on the writer: how the computed rows were shared out
  std::size_t dropped_journal_lines = 0;  // cut short or corrupt lines of the journal resumed
};

// Throws on a duplicate key, a key or row with a tab or line break, a journal of another
// signature, or the first job that threw (in a distributed run the caller then aborts the job).
// On stderr, so that stdout stays the same bytes however the grid ran: what this run computed,
// what the journal already held, and how the ranks shared the work.
void report_grid(const GridOutcome& outcome, const ParallelSession& session, const std::string& journal);

GridOutcome run_grid(const ParallelSession& session, const std::vector<std::string>& keys, const ComputeRow& compute,
                     const GridOptions& options);

}  // namespace dynweigh::tools::grid
