#pragma once
// The writer's side of a grid: every row in its job's place, each new one journalled as it
// arrives (from a local thread or another rank), and the progress reported.
#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "results_journal.hpp"

namespace dynweigh::tools::grid {

class RowCollector {
 public:
  using Progress = std::function<void(std::size_t finished, std::size_t total)>;
  RowCollector(const std::vector<std::string>& keys, JournalWriter* journal, Progress progress);

  // A row the journal already held: not journalled again, not counted as computed.
  void adopt(std::size_t job, std::string row);
  // A row computed now, by `rank` (0: the writer's own threads).
  void accept(std::size_t job, std::string row, int rank = 0);

  std::size_t missing() const { return keys_.size() - filled_; }
  std::size_t computed() const { return computed_; }
  const std::vector<std::size_t>& computed_by_rank() const { return computed_by_rank_; }
  std::vector<std::string> take_rows();

 private:
  void place(std::size_t job, std::string row);

  const std::vector<std::string>& keys_;
  JournalWriter* journal_;
  Progress progress_;
  std::vector<std::string> rows_;
  std::vector<bool> filled_flags_;
  std::size_t filled_ = 0;
  std::size_t computed_ = 0;
  std::vector<std::size_t> computed_by_rank_;
};

}  // namespace dynweigh::tools::grid
