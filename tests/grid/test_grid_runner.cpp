// The scenario grid runner in one process: rows in the jobs' order whatever the threads, and a
// resume that computes exactly the jobs the journal lacks.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>

#include "grid_runner.hpp"

namespace grid = dynweigh::tools::grid;

namespace {

std::vector<std::string> keys_of(std::size_t count) {
  std::vector<std::string> keys;
  for (std::size_t i = 0; i < count; ++i) keys.push_back("job=" + std::to_string(i));
  return keys;
}

// A row that depends only on its key; jobs take unequal times so threads finish out of order.
std::string row_of(const std::string& key) {
  const std::size_t number = std::stoul(key.substr(4));
  std::this_thread::sleep_for(std::chrono::microseconds((number * 7919) % 3000));
  return "square=" + std::to_string(number * number);
}

std::string temporary_journal(const std::string& name) {
  const auto path = std::filesystem::temp_directory_path() / ("dynweigh_grid_" + name + ".journal");
  std::filesystem::remove(path);
  return path.string();
}

TEST(GridRunner, RowsComeBackInTheJobsOrderWhateverTheThreads) {
  const grid::ParallelSession single;
  const auto keys = keys_of(40);
  for (unsigned threads : {1u, 3u, 8u}) {
    grid::GridOptions options;
    options.threads = threads;
    const grid::GridOutcome out = grid::run_grid(single, keys, [&](std::size_t i) { return row_of(keys[i]); }, options);
    ASSERT_EQ(out.rows.size(), keys.size());
    for (std::size_t i = 0; i < keys.size(); ++i) EXPECT_EQ(out.rows[i], "square=" + std::to_string(i * i));
    EXPECT_EQ(out.computed, keys.size());
    EXPECT_EQ(out.skipped, 0u);
  }
}

TEST(GridRunner, AResumeComputesExactlyTheJobsTheJournalLacks) {
  const grid::ParallelSession single;
  const auto keys = keys_of(20);
  const std::string journal = temporary_journal("resume");
  grid::GridOptions options;
  options.threads = 3;
  options.journal_path = journal;
  options.signature = "squares";
  const auto first = grid::run_grid(single, keys, [&](std::size_t i) { return row_of(keys[i]); }, options);

  // Keep the header and every second row, then cut the last kept line in the middle.
  std::ifstream in(journal);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  ASSERT_EQ(lines.size(), keys.size() + 1);
  std::set<std::string> kept;
  std::string damaged = lines[0] + "\n";
  for (std::size_t i = 1; i < lines.size(); i += 2) {
    damaged += lines[i] + "\n";
    kept.insert(lines[i].substr(0, lines[i].find('\t')));
  }
  damaged += lines[2].substr(0, lines[2].size() / 2);  // a row being written when the writer died
  std::ofstream(journal, std::ios::trunc) << damaged;

  std::mutex mutex;
  std::set<std::string> computed;
  options.resume = true;
  const auto resumed = grid::run_grid(
      single, keys,
      [&](std::size_t i) {
        {
          const std::lock_guard<std::mutex> lock(mutex);
          computed.insert(keys[i]);
        }
        return row_of(keys[i]);
      },
      options);
  EXPECT_EQ(resumed.rows, first.rows);
  EXPECT_EQ(resumed.skipped, kept.size());
  EXPECT_EQ(resumed.computed, keys.size() - kept.size());
  EXPECT_EQ(resumed.dropped_journal_lines, 1u);
  for (const auto& key : keys) EXPECT_NE(kept.count(key), computed.count(key)) << key;

  // A resume of the complete journal computes nothing.
  const auto again = grid::run_grid(single, keys, [&](std::size_t) -> std::string { throw std::logic_error("ran"); },
                                    options);
  EXPECT_EQ(again.rows, first.rows);
  EXPECT_EQ(again.computed, 0u);
  std::filesystem::remove(journal);
}

TEST(GridRunner, AJobThatFailsFailsTheGridWithItsMessage) {
  const grid::ParallelSession single;
  const auto keys = keys_of(10);
  grid::GridOptions options;
  options.threads = 2;
  try {
    grid::run_grid(single, keys,
                   [&](std::size_t i) -> std::string {
                     if (i == 6) throw std::runtime_error("scene six is malformed");
                     return row_of(keys[i]);
                   },
                   options);
    FAIL() << "the grid did not fail";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "scene six is malformed");
  }
}

TEST(GridRunner, DuplicateKeysAResumeWithoutJournalAndRowsWithLineBreaksAreRefused) {
  const grid::ParallelSession single;
  const auto row = [](std::size_t) { return std::string("x"); };
  EXPECT_THROW(grid::run_grid(single, {"a", "b", "a"}, row, {}), std::invalid_argument);
  grid::GridOptions resume;
  resume.resume = true;
  EXPECT_THROW(grid::run_grid(single, {"a"}, row, resume), std::invalid_argument);
  EXPECT_THROW(grid::run_grid(single, {"a"}, [](std::size_t) { return std::string("x\ny"); }, {}),
               std::invalid_argument);
}

}  // namespace
