// The logbook wired to the indicator: every certified RESULT appended and numbered, kept in the
// settings' non-volatile memory across a restart, listed by `log`, and a write cut at any byte of
// a result's record loses that record alone.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "dynweigh/firmware/fill_statistics.hpp"
#include "dynweigh/firmware/ram_nvm.hpp"
#include "dynweigh/hal/host/cuttable_nvm.hpp"
#include "dynweigh/hal/host/file_settings_store.hpp"
#include "support/console_session.hpp"
#include "support/temp_file.hpp"

namespace dynweigh::testing {
namespace {


TEST(FillLogbook, ResultsSurviveARestartWithTheSameNvmFile) {
  TempFile file{"dynweigh_logbook"};
  std::vector<std::string> results;
  for (int run = 0; run < 2; ++run) {
    // As dynweigh-fw --nvm FILE starts: the file prepared, its record loaded (none the first time).
    hal::host::prepare_nvm_file(file.path(), /*reset=*/false);
    hal::host::FileSettingsStore store(file.path());
    firmware::PersistentSettings stored;
    const bool loaded = store.load(stored);
    ConsoleSession c(sim::default_scene(), 1, loaded ? std::optional(stored) : std::nullopt, &store);
    if (!loaded) c.run({"param stable_ms 500"});  // saves the starting (factory-calibrated) settings
    for (const std::string& line : lines_starting(c.run({"dose 300", "dose 400"}), "RESULT ")) {
      results.push_back(line);
    }
  }
  ASSERT_EQ(results.size(), 4u);
  for (std::size_t i = 0; i < results.size(); ++i) EXPECT_EQ(field(results[i], "seq"), std::to_string(i + 1));

  hal::host::FileSettingsStore store(file.path());
  ConsoleSession c(sim::default_scene(), 1, std::nullopt, &store);
  const std::vector<std::string> log = lines_starting(c.run({"log"}), "LOG ");
  ASSERT_EQ(log.size(), 4u);
  for (std::size_t i = 0; i < log.size(); ++i) {
    EXPECT_EQ(field(log[i], "seq"), field(results[i], "seq"));
    EXPECT_EQ(field(log[i], "target"), field(results[i], "target"));
    EXPECT_EQ(field(log[i], "final"), field(results[i], "final"));
    EXPECT_EQ(field(log[i], "tolerance"), field(results[i], "tolerance"));
    EXPECT_EQ(field(log[i], "topups"), field(results[i], "topups"));
    EXPECT_EQ(field(log[i], "material"), "0");
    EXPECT_EQ(field(log[i], "crc"), "ok");
  }
  EXPECT_LT(std::stoul(field(log[0], "jiffy")), std::stoul(field(log[1], "jiffy")));
  // By sequence number, and the last n.
  const std::vector<std::string> middle = lines_starting(c.run({"log 2 3"}), "LOG ");
  ASSERT_EQ(middle.size(), 2u);
  EXPECT_EQ(middle[0], log[1]);
  EXPECT_EQ(middle[1], log[2]);
  const std::vector<std::string> last = lines_starting(c.run({"log 1"}), "LOG ");
  ASSERT_EQ(last.size(), 1u);
  EXPECT_EQ(last[0], log[3]);
  EXPECT_EQ(c.run({"log 5 2"}), "ERR 2 need <from> <= <to>\n");
  EXPECT_EQ(c.run({"log 0"}), "ERR 2 usage: log [<n>]\n");
}

// The board's store over a memory that can lose power: the settings' slots, then the logbook.
class CuttableStore final : public hal::SettingsStore {
 public:
  static constexpr std::size_t kSlots = 64;
  CuttableStore() { logbook_.open(); }
  bool load(firmware::PersistentSettings& settings) override { return slots_.load(settings); }
  bool save(const firmware::PersistentSettings& settings) override { return slots_.save(settings); }
  firmware::Logbook* logbook() override { return &logbook_; }
  hal::host::CuttableNvm& nvm() { return nvm_; }

 private:
  hal::host::CuttableNvm nvm_{firmware::kSettingsSlotsBytes + kSlots * firmware::kLogRecordSize};
  firmware::SettingsSlots slots_{nvm_};
  firmware::Logbook logbook_{nvm_, firmware::kSettingsSlotsBytes, kSlots};
};

TEST(FillLogbook, AResultsWriteCutAtAnyByteLosesOnlyThatRecord) {
  CuttableStore store;
  ConsoleSession c(sim::default_scene(), 1, std::nullopt, &store);
  // settings in their slots beside the logbook; class 10: no top-up, so the result is the first write
  c.run({"param stable_ms 500", "param class 10"});
  std::vector<std::string> kept = lines_starting(c.run({"dose 200", "dose 200"}), "RESULT ");
  ASSERT_EQ(kept.size(), 2u);
  for (std::size_t cut = 0; cut < firmware::kLogRecordSize; ++cut) {
    store.nvm().arm_cut(cut, std::uint8_t(0xA5));
    const std::string out = c.run({"dose 200"});
    ASSERT_NE(out.find("ERR 4 fault nvm_error"), std::string::npos) << "cut " << cut << ": " << out;
    EXPECT_NE(out.find(" seq=0"), std::string::npos) << out;
    // A restart reads every record before the cut, intact, and the cut one not at all.
    firmware::Logbook reopened(store.nvm(), firmware::kSettingsSlotsBytes, CuttableStore::kSlots);
    ASSERT_TRUE(reopened.open());
    ASSERT_EQ(reopened.last_sequence(), kept.size()) << "cut " << cut;
    for (std::size_t i = 0; i < kept.size(); ++i) {
      firmware::LogRecord r;
      ASSERT_TRUE(reopened.read(std::uint32_t(i + 1), r)) << "cut " << cut << " record " << i + 1;
      EXPECT_EQ(std::to_string(r.final_dg / 10), field(kept[i], "final"));
    }
    // The power is back: the next result takes the sequence number the cut one lost.
    const std::string next = c.run({"clearfault", "dose 200"});
    const std::vector<std::string> result = lines_starting(next, "RESULT ");
    ASSERT_EQ(result.size(), 1u) << next;
    EXPECT_EQ(field(result[0], "seq"), std::to_string(kept.size() + 1));
    kept.push_back(result[0]);
  }
  firmware::PersistentSettings settings;
  ASSERT_TRUE(store.load(settings));  // the settings beside it never touched
  EXPECT_FLOAT_EQ(settings.parameters.get(firmware::ParameterId::stable_ms), 500.0f);
}

TEST(FillLogbook, WithoutStorageTheBoardKeepsTheResultsInRam) {
  ConsoleSession c;
  const std::string out = c.run({"dose 300", "log"});
  const std::vector<std::string> results = lines_starting(out, "RESULT ");
  const std::vector<std::string> log = lines_starting(out, "LOG ");
  ASSERT_EQ(results.size(), 1u);
  ASSERT_EQ(log.size(), 1u);
  EXPECT_EQ(field(results[0], "seq"), "1");
  EXPECT_EQ(field(log[0], "final"), field(results[0], "final"));
}

}  // namespace
}  // namespace dynweigh::testing

namespace dynweigh::testing {
namespace {

double number(const std::string& line, const std::string& key) { return std::stod(field(line, key)); }

// `stats` against the same values computed here from the `log` lines it reads.
TEST(FillStatistics, EqualTheValuesComputedFromTheLogbook) {
  ConsoleSession c;
  EXPECT_EQ(field(lines_of(c.run({"stats"}))[0], "count"), "0");
  std::vector<std::string> script;
  for (int i = 0; i < 6; ++i) script.push_back("dose " + std::to_string(300 + 10 * (i % 3)));
  c.run(script, 100000);
  const std::vector<std::string> log = lines_starting(c.run({"log 100"}), "LOG ");
  ASSERT_EQ(log.size(), 6u);
  double sum = 0.0, lo = 1e9, hi = -1e9, targets = 0.0;
  for (const std::string& line : log) {
    const double final_g = number(line, "final");
    sum += final_g;
    targets += number(line, "target");
    lo = std::min(lo, final_g);
    hi = std::max(hi, final_g);
  }
  const double mean = sum / 6.0;
  double squares = 0.0, worst = 0.0;
  for (const std::string& line : log) {
    squares += (number(line, "final") - mean) * (number(line, "final") - mean);
    worst = std::max(worst, std::abs(number(line, "final") - mean));
  }
  const double sd = std::sqrt(squares / 5.0);
  const std::string stats = lines_starting(c.run({"stats"}), "STATS ")[0];
  EXPECT_EQ(field(stats, "material"), "0");
  EXPECT_EQ(field(stats, "count"), "6");
  EXPECT_NEAR(number(stats, "mean_g"), mean, 0.006);
  EXPECT_NEAR(number(stats, "sd_g"), sd, 0.006);
  EXPECT_NEAR(number(stats, "min_g"), lo, 0.06);
  EXPECT_NEAR(number(stats, "max_g"), hi, 0.06);
  EXPECT_NEAR(number(stats, "total_kg"), sum / 1000.0, 0.0006);
  EXPECT_GE(std::stoi(field(stats, "valve_cycles")), 6);
  EXPECT_GT(number(stats, "dosing_s"), 0.0);
  EXPECT_EQ(field(stats, "gate_cycles"), "0");
  // The class: targets 300..320 g mixed, so the spread is the targets' (X(1) at 310 g: 6.5 g).
  EXPECT_NE(field(stats, "class"), "");
  // Reset: from the next fill on.
  c.run({"stats reset"});
  EXPECT_EQ(field(lines_starting(c.run({"stats"}), "STATS ")[0], "count"), "0");
  const std::string result = lines_starting(c.run({"dose 300"}), "RESULT ")[0];
  const std::string after = lines_starting(c.run({"stats"}), "STATS ")[0];
  EXPECT_EQ(field(after, "count"), "1");
  EXPECT_NEAR(number(after, "mean_g"), number(result, "final"), 0.006);
  EXPECT_EQ(field(after, "sd_g"), "0");
}

TEST(FillStatistics, OnlyTheLastHundredFills) {
  firmware::RamLogbook<130> ram;
  for (int i = 1; i <= 120; ++i) {
    firmware::LogRecord r;
    r.target_dg = 10000;
    r.final_dg = i <= 20 ? 50000 : 10000 + 10 * (i % 2);  // the first 20 far off, then 1000.0/1001.0 g
    ASSERT_TRUE(ram.logbook().append(r));
  }
  const firmware::FillStatistics s = firmware::fill_statistics(ram.logbook(), 0, 0, 100);
  EXPECT_EQ(s.count, 100u);
  EXPECT_FLOAT_EQ(s.min_g, 1000.0f);
  EXPECT_FLOAT_EQ(s.max_g, 1001.0f);
  EXPECT_NEAR(s.mean_g, 1000.5f, 1e-3);
  // Within 0.5 g of the mean and 0.5 g of the target: X(0.1) at 1000 g allows 1.05 g and 0.375 g
  // of bias; 0.5 g of bias needs X(0.2) (0.75 g).
  EXPECT_FLOAT_EQ(s.class_x, 0.2f);
}

}  // namespace
}  // namespace dynweigh::testing
