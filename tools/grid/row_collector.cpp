#include "row_collector.hpp"

#include <stdexcept>

namespace dynweigh::tools::grid {

RowCollector::RowCollector(const std::vector<std::string>& keys, JournalWriter* journal, Progress progress)
    : keys_(keys), journal_(journal), progress_(std::move(progress)), rows_(keys.size()),
      filled_flags_(keys.size(), false) {}

void RowCollector::place(std::size_t job, std::string row) {
  if (job >= keys_.size()) throw std::runtime_error("a row came back for job " + std::to_string(job) + " of none");
  if (filled_flags_[job]) throw std::runtime_error("job '" + keys_[job] + "' came back twice");
  check_journal_field("the row of job '" + keys_[job] + "'", row);
  rows_[job] = std::move(row);
  filled_flags_[job] = true;
  ++filled_;
  if (progress_) progress_(filled_, keys_.size());
}

void RowCollector::adopt(std::size_t job, std::string row) { place(job, std::move(row)); }

void RowCollector::accept(std::size_t job, std::string row, int rank) {
  place(job, std::move(row));
  ++computed_;
  if (computed_by_rank_.size() <= std::size_t(rank)) computed_by_rank_.resize(std::size_t(rank) + 1, 0);
  ++computed_by_rank_[std::size_t(rank)];
  if (journal_) journal_->append(keys_[job], rows_[job]);
}

std::vector<std::string> RowCollector::take_rows() {
  if (missing() != 0) throw std::runtime_error(std::to_string(missing()) + " jobs of the grid never came back");
  return std::move(rows_);
}

}  // namespace dynweigh::tools::grid
