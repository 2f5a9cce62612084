#include "grid_runner.hpp"

#include <cstdio>
#include <memory>
#include <set>
#include <stdexcept>

#include "row_collector.hpp"
#ifdef DYNWEIGH_GRID_MPI
#include "mpi_dispatch.hpp"
#endif

namespace dynweigh::tools::grid {
namespace {

void check_keys(const std::vector<std::string>& keys) {
  std::set<std::string> seen;
  for (const auto& key : keys) {
    if (key.empty()) throw std::invalid_argument("a job of the grid has an empty key");
    check_journal_field("job key", key);
    if (!seen.insert(key).second) throw std::invalid_argument("the grid names job '" + key + "' twice");
  }
}

void run_on_threads(JobQueue& queue, const ComputeRow& compute, unsigned threads, RowCollector& collector) {
  LocalWorkers workers(queue, compute, std::max(1u, threads));
  for (FinishedJob finished; collector.missing() > 0;) {
    if (workers.next_finished(finished, std::chrono::milliseconds(100))) {
      collector.accept(finished.job, std::move(finished.row));
    }
  }
}

GridOutcome write_rows(const ParallelSession& session, const std::vector<std::string>& keys,
                       const ComputeRow& compute, const GridOptions& options) {
  if (options.resume && options.journal_path.empty()) throw std::invalid_argument("a resume needs a journal");
  JournalContents previous;
  if (options.resume) previous = read_journal(options.journal_path, options.signature);
  std::unique_ptr<JournalWriter> journal;
  if (!options.journal_path.empty()) {
    journal = std::make_unique<JournalWriter>(options.journal_path, options.signature, previous);
  }
  RowCollector collector(keys, journal.get(), options.progress);
  std::vector<std::size_t> pending;
  for (std::size_t job = 0; job < keys.size(); ++job) {
    const auto done = previous.rows.find(keys[job]);
    if (done != previous.rows.end()) {
      collector.adopt(job, done->second);
    } else {
      pending.push_back(job);
    }
  }
  GridOutcome outcome;
  outcome.skipped = keys.size() - pending.size();
  outcome.dropped_journal_lines = previous.dropped_lines;
  JobQueue queue(std::move(pending));
#ifdef DYNWEIGH_GRID_MPI
  if (session.distributed()) {
    deal_out_jobs(session, keys, queue, compute, collector);
  } else {
    run_on_threads(queue, compute, options.threads, collector);
  }
#else
  (void)session;
  run_on_threads(queue, compute, options.threads, collector);
#endif
  outcome.computed = collector.computed();
  outcome.computed_by_rank = collector.computed_by_rank();
  outcome.computed_by_rank.resize(std::size_t(session.size()), 0);
  outcome.rows = collector.take_rows();
  return outcome;
}

}  // namespace

GridOutcome run_grid(const ParallelSession& session, const std::vector<std::string>& keys, const ComputeRow& compute,
                     const GridOptions& options) {
  check_keys(keys);
  if (session.writer()) return write_rows(session, keys, compute, options);
  GridOutcome outcome;
#ifdef DYNWEIGH_GRID_MPI
  outcome.computed = serve_jobs(keys, compute);
#endif
  return outcome;
}

void report_grid(const GridOutcome& outcome, const ParallelSession& session, const std::string& journal) {
  std::string by_rank;
  for (std::size_t count : outcome.computed_by_rank) by_rank += (by_rank.empty() ? "" : ",") + std::to_string(count);
  std::fprintf(stderr, "computed=%zu skipped=%zu dropped_journal_lines=%zu ranks=%d computed_by_rank=%s journal=%s\n",
               outcome.computed, outcome.skipped, outcome.dropped_journal_lines, session.size(), by_rank.c_str(),
               journal.empty() ? "none" : journal.c_str());
}

}  // namespace dynweigh::tools::grid
