// The grid's journal: what a crash leaves behind is read back as the intact rows only.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "results_journal.hpp"

namespace grid = dynweigh::tools::grid;

namespace {

class JournalTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("dynweigh_journal_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
    path_ = (dir_ / "grid.journal").string();
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  void write_three_rows() {
    grid::JournalWriter writer(path_, "test seeds=3", {});
    writer.append("a", "row of a");
    writer.append("b", "row of b");
    writer.append("c", "row of c");
  }
  std::string text() const {
    std::ifstream in(path_, std::ios::binary);
    std::stringstream buffer;
    buffer << in.rdbuf();
    return buffer.str();
  }
  void replace_text(const std::string& text) const { std::ofstream(path_, std::ios::binary | std::ios::trunc) << text; }

  std::filesystem::path dir_;
  std::string path_;
};

TEST_F(JournalTest, EveryAppendedRowReadsBack) {
  write_three_rows();
  const grid::JournalContents contents = grid::read_journal(path_, "test seeds=3");
  ASSERT_EQ(contents.rows.size(), 3u);
  EXPECT_EQ(contents.rows.at("b"), "row of b");
  EXPECT_EQ(contents.dropped_lines, 0u);
}

TEST_F(JournalTest, ALastLineCutShortAtAnyByteIsDroppedAndTheOthersKept) {
  write_three_rows();
  const std::string whole = text();
  const std::size_t last_line = whole.rfind('\n', whole.size() - 2) + 1;
  for (std::size_t cut = last_line + 1; cut < whole.size(); ++cut) {
    replace_text(whole.substr(0, cut));
    const grid::JournalContents contents = grid::read_journal(path_, "test seeds=3");
    EXPECT_EQ(contents.rows.size(), 2u) << "cut at byte " << cut;
    EXPECT_EQ(contents.rows.count("c"), 0u) << "cut at byte " << cut;
    EXPECT_EQ(contents.dropped_lines, 1u) << "cut at byte " << cut;
  }
}

TEST_F(JournalTest, ACorruptLineInTheMiddleIsDropped) {
  write_three_rows();
  std::string damaged = text();
  damaged[damaged.find("row of b") + 4] = 'X';
  replace_text(damaged);
  const grid::JournalContents contents = grid::read_journal(path_, "test seeds=3");
  EXPECT_EQ(contents.rows.size(), 2u);
  EXPECT_EQ(contents.rows.count("b"), 0u);
  EXPECT_EQ(contents.dropped_lines, 1u);
}

TEST_F(JournalTest, AJournalOfAnotherGridIsRefused) {
  write_three_rows();
  EXPECT_THROW(grid::read_journal(path_, "test seeds=4"), std::runtime_error);
}

TEST_F(JournalTest, NoJournalOrAHeaderCutShortReadsAsNoRows) {
  EXPECT_TRUE(grid::read_journal(path_, "test seeds=3").rows.empty());
  replace_text("# dynweigh grid jour");
  EXPECT_TRUE(grid::read_journal(path_, "test seeds=3").rows.empty());
}

TEST_F(JournalTest, AResumedJournalHoldsOnlyIntactLinesAndAppendsOnANewLine) {
  write_three_rows();
  const std::string whole = text();
  replace_text(whole.substr(0, whole.size() - 5));
  {
    grid::JournalWriter writer(path_, "test seeds=3", grid::read_journal(path_, "test seeds=3"));
    writer.append("c", "row of c again");
  }
  const grid::JournalContents contents = grid::read_journal(path_, "test seeds=3");
  EXPECT_EQ(contents.dropped_lines, 0u);
  ASSERT_EQ(contents.rows.size(), 3u);
  EXPECT_EQ(contents.rows.at("c"), "row of c again");
}

TEST_F(JournalTest, KeysAndRowsWithTabsOrLineBreaksAreRefused) {
  grid::JournalWriter writer(path_, "test seeds=3", {});
  EXPECT_THROW(grid::check_journal_field("key", "a\tb"), std::invalid_argument);
  EXPECT_THROW(grid::check_journal_field("row", "a\nb"), std::invalid_argument);
  EXPECT_NO_THROW(grid::check_journal_field("row", "a b=1"));
}

}  // namespace
