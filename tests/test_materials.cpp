// The material table on the console (list, select, edit, bad input), persisted with the settings
// across a restart; each material's statistics against the logbook, and its totalizers kept
// power-safe (a restart, and a write cut at every byte).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "dynweigh/firmware/totalizers.hpp"
#include "dynweigh/hal/host/cuttable_nvm.hpp"
#include "dynweigh/hal/host/file_settings_store.hpp"
#include "support/console_session.hpp"
#include "support/temp_file.hpp"

namespace dynweigh::testing {
namespace {

double number(const std::string& line, const std::string& key) { return std::stod(field(line, key)); }


// A board started on `file` as dynweigh-fw --nvm starts: the file prepared, its record loaded.
struct BoardOnFile {
  explicit BoardOnFile(const std::string& path) : store((hal::host::prepare_nvm_file(path, false), path)) {
    firmware::PersistentSettings stored;
    const bool loaded = store.load(stored);
    session = std::make_unique<ConsoleSession>(sim::default_scene(), 1, loaded ? std::optional(stored) : std::nullopt,
                                               &store);
  }
  hal::host::FileSettingsStore store;
  std::unique_ptr<ConsoleSession> session;
};

TEST(Materials, ListSelectAndEditOnTheConsole) {
  ConsoleSession c;
  const std::string first = c.run({"material"});
  const std::vector<std::string> listed = lines_starting(first, "MATERIAL ");
  ASSERT_EQ(listed.size(), 1u) << first;
  EXPECT_EQ(field(listed[0], "n"), "0");
  EXPECT_EQ(field(listed[0], "name"), "material0");
  EXPECT_EQ(field(listed[0], "density"), "1550");
  EXPECT_EQ(field(listed[0], "selected"), "1");
  EXPECT_EQ(lines_of(first).back(), "OK");

  const std::string edited = c.run({"material 4 name wheat", "material 4 density 780", "material 4 class 0.5"});
  EXPECT_EQ(lines_starting(edited, "OK").size(), 3u) << edited;
  const std::string selected = c.run({"material 4", "param density", "param class"});
  EXPECT_NE(selected.find("density=780\n"), std::string::npos) << selected;
  EXPECT_NE(selected.find("class=0.5\n"), std::string::npos) << selected;
  // `param density` edits the selected material's entry; material 0 keeps its own.
  c.run({"param density 800"});
  std::vector<std::string> table = lines_starting(c.run({"material"}), "MATERIAL ");
  ASSERT_EQ(table.size(), 2u);
  EXPECT_EQ(field(table[1], "n"), "4");
  EXPECT_EQ(field(table[1], "name"), "wheat");
  EXPECT_EQ(field(table[1], "density"), "800");
  EXPECT_EQ(field(table[1], "class"), "0.5");
  EXPECT_EQ(field(table[1], "selected"), "1");
  EXPECT_EQ(field(table[0], "density"), "1550");
  EXPECT_NE(c.run({"material 0", "param density"}).find("density=1550\n"), std::string::npos);
  // Selecting a material never named defines it with the defaults.
  const std::string fresh = lines_starting(c.run({"material 15"}), "MATERIAL ")[0];
  EXPECT_EQ(field(fresh, "name"), "material15");
  EXPECT_EQ(field(fresh, "density"), "1550");
}

TEST(Materials, BadInputIsErr2AndChangesNothing) {
  ConsoleSession c;
  const std::vector<std::string> bad = {
      "material 16",           "material -1",        "material x",          "material 1.5",
      "material 2 name",       "material 2 name a_name_of_16_chr", "material 2 name bad/char",
      "material 2 density 99", "material 2 density 5001", "material 2 density 1e3", "material 2 density",
      "material 2 class 0",    "material 2 class 101", "material 2 colour red", "material 2 name two words",
      "stats 16",              "stats x",            "stats reset 16",      "stats 1 2",
      "stats reset 1 2",       "stats -1"};
  for (const std::string& line : bad) {
    const std::vector<std::string> out = lines_of(c.run({line}));
    ASSERT_EQ(out.size(), 1u) << line;
    EXPECT_EQ(out[0].rfind("ERR 2 ", 0), 0u) << line << ": " << out[0];
  }
  const std::vector<std::string> table = lines_starting(c.run({"material"}), "MATERIAL ");
  ASSERT_EQ(table.size(), 1u);
  EXPECT_EQ(field(table[0], "n"), "0");
  EXPECT_NE(c.run({"param density"}).find("density=1550\n"), std::string::npos);
}

TEST(Materials, TheDoseUsesTheSelectedMaterialsDensityAndRecordsItsNumber) {
  ConsoleSession by_material;
  by_material.run({"material 3 density 1200", "material 3"});
  const std::string out = by_material.run({"dose 500", "log 1"});
  const std::vector<std::string> result = lines_starting(out, "RESULT ");
  ASSERT_EQ(result.size(), 1u) << out;
  EXPECT_EQ(field(result[0], "material"), "3");
  EXPECT_EQ(field(lines_starting(out, "LOG ")[0], "material"), "3");
  // The same dose with the density set as a parameter on material 0: the same fill.
  ConsoleSession by_parameter;
  by_parameter.run({"param density 1200"});
  const std::string same = lines_starting(by_parameter.run({"dose 500"}), "RESULT ")[0];
  EXPECT_EQ(field(same, "material"), "0");
  // The close comes at the same jiffy; the top-up pulses after it each land within a gram of the
  // same mass (the load cell's noise differs by the jiffies the two set-ups took).
  EXPECT_EQ(field(result[0], "cutoff"), field(same, "cutoff"));
  EXPECT_NEAR(std::stod(field(result[0], "final")), std::stod(field(same, "final")), 2.0) << result[0] << '\n' << same;
}

TEST(Materials, TheTableSurvivesARestartWithTheSameNvmFile) {
  TempFile file{"dynweigh_materials"};
  std::vector<std::string> before;
  {
    BoardOnFile board(file.path());
    board.session->run({"material 2 name barley", "material 2 density 640", "material 7 name rye", "material 7 class 2",
                        "material 2"});
    before = lines_starting(board.session->run({"material"}), "MATERIAL ");
  }
  ASSERT_EQ(before.size(), 3u);
  BoardOnFile board(file.path());
  const std::vector<std::string> after = lines_starting(board.session->run({"material"}), "MATERIAL ");
  EXPECT_EQ(after, before);
  EXPECT_NE(board.session->run({"param density"}).find("density=640\n"), std::string::npos);
}

struct Expected {
  int count = 0;
  double mean = 0, sd = 0, lo = 0, hi = 0, total = 0;
};

Expected from_log(const std::vector<std::string>& log, const std::string& material) {
  std::vector<double> finals;
  for (const std::string& line : log) {
    if (field(line, "material") == material) finals.push_back(number(line, "final"));
  }
  Expected e;
  e.count = int(finals.size());
  if (finals.empty()) return e;
  for (double f : finals) e.total += f;
  e.mean = e.total / double(finals.size());
  double squares = 0.0;
  for (double f : finals) squares += (f - e.mean) * (f - e.mean);
  e.sd = finals.size() > 1 ? std::sqrt(squares / double(finals.size() - 1)) : 0.0;
  e.lo = *std::min_element(finals.begin(), finals.end());
  e.hi = *std::max_element(finals.begin(), finals.end());
  return e;
}

void expect_stats(const std::string& stats, const Expected& e) {
  EXPECT_EQ(field(stats, "count"), std::to_string(e.count)) << stats;
  EXPECT_NEAR(number(stats, "mean_g"), e.mean, 0.006) << stats;
  EXPECT_NEAR(number(stats, "sd_g"), e.sd, 0.006) << stats;
  EXPECT_NEAR(number(stats, "min_g"), e.lo, 0.06) << stats;
  EXPECT_NEAR(number(stats, "max_g"), e.hi, 0.06) << stats;
  EXPECT_NEAR(number(stats, "total_kg"), e.total / 1000.0, 0.0006) << stats;
  EXPECT_GE(std::stoi(field(stats, "valve_cycles")), e.count) << stats;
}

TEST(MaterialStatistics, EachMaterialsEqualTheValuesComputedFromTheLogbook) {
  ConsoleSession c;
  c.run({"material 1 name sand", "material 2 name gravel"});
  std::vector<std::string> script;
  for (int i = 0; i < 8; ++i) {
    script.push_back(i % 2 == 0 ? "material 1" : "material 2");
    script.push_back("dose " + std::to_string(250 + 20 * (i % 3) + 40 * (i % 2)));
  }
  c.run(script, 200000);
  const std::vector<std::string> log = lines_starting(c.run({"log 100"}), "LOG ");
  ASSERT_EQ(log.size(), 8u);
  const Expected sand = from_log(log, "1"), gravel = from_log(log, "2");
  ASSERT_EQ(sand.count, 4);
  ASSERT_EQ(gravel.count, 4);
  expect_stats(lines_starting(c.run({"stats 1"}), "STATS ")[0], sand);
  const std::string gravel_stats = lines_starting(c.run({"stats"}), "STATS ")[0];  // the selected: 2
  EXPECT_EQ(field(gravel_stats, "material"), "2");
  expect_stats(gravel_stats, gravel);
  EXPECT_EQ(field(lines_starting(c.run({"stats 0"}), "STATS ")[0], "count"), "0");
  const std::vector<std::string> table = lines_starting(c.run({"material"}), "MATERIAL ");
  ASSERT_EQ(table.size(), 3u);
  EXPECT_EQ(field(table[1], "fills"), "4");
  EXPECT_EQ(field(table[2], "fills"), "4");
  // `stats reset 1` resets sand's alone.
  c.run({"stats reset 1"});
  const std::string reset = lines_starting(c.run({"stats 1"}), "STATS ")[0];
  EXPECT_EQ(field(reset, "count"), "0");
  EXPECT_EQ(field(reset, "total_kg"), "0.000");
  EXPECT_EQ(field(reset, "valve_cycles"), "0");
  expect_stats(lines_starting(c.run({"stats 2"}), "STATS ")[0], gravel);
}

TEST(MaterialStatistics, TotalizersSurviveARestartWithTheSameNvmFile) {
  TempFile file{"dynweigh_materials"};
  std::string before;
  {
    BoardOnFile board(file.path());
    board.session->run({"material 1", "dose 300", "dose 350"});
    before = lines_starting(board.session->run({"stats 1"}), "STATS ")[0];
  }
  EXPECT_EQ(field(before, "count"), "2");
  EXPECT_NE(field(before, "total_kg"), "0.000");
  BoardOnFile board(file.path());
  const std::string after = lines_starting(board.session->run({"stats 1"}), "STATS ")[0];
  EXPECT_EQ(after, before);
}

// A version-5 --nvm file (its settings slots smaller than today's, the logbook right behind them):
// grown on start, its logbook moved behind today's slots, every record still readable.
TEST(MaterialStatistics, AVersion5NvmFilesLogbookIsMovedAndKept) {
  TempFile file{"dynweigh_materials"};
  constexpr std::size_t kOldLogbook = hal::host::kVersion5FileBytes - hal::host::kFileLogbookSlots * firmware::kLogRecordSize;
  std::vector<std::uint8_t> bytes(hal::host::kVersion5FileBytes, 0xFF);
  for (std::uint32_t seq = 1; seq <= 3; ++seq) {
    firmware::LogRecord r;
    r.sequence = seq;
    r.target_dg = 3000;
    r.final_dg = 3000 + 10 * std::int32_t(seq);
    firmware::encode_log_record(r, bytes.data() + kOldLogbook + (seq - 1) * firmware::kLogRecordSize);
  }
  {
    std::FILE* f = std::fopen(file.path().c_str(), "wb");
    ASSERT_NE(f, nullptr);
    ASSERT_EQ(std::fwrite(bytes.data(), 1, bytes.size(), f), bytes.size());
    std::fclose(f);
  }
  EXPECT_EQ(hal::host::prepare_nvm_file(file.path(), false), hal::host::NvmFile::sized);
  hal::host::FileSettingsStore store(file.path());
  ASSERT_EQ(store.logbook()->last_sequence(), 3u);
  for (std::uint32_t seq = 1; seq <= 3; ++seq) {
    firmware::LogRecord r;
    ASSERT_TRUE(store.logbook()->read(seq, r)) << seq;
    EXPECT_EQ(r.final_dg, 3000 + 10 * std::int32_t(seq));
  }
  firmware::MaterialTotals totals;
  EXPECT_FALSE(store.totalizers()->load(totals));  // erased: counted from here on
}

firmware::MaterialTotals totals_generation(std::uint32_t n) {
  firmware::MaterialTotals t;
  for (std::size_t m = 0; m < firmware::MaterialTable::kMaterials; ++m) {
    t.material[m].total_g = 5000000000ull * n + m;  // beyond 32 bits
    t.material[m].fills = n + std::uint32_t(m);
    t.material[m].valve_cycles = 3 * n;
    t.material[m].gate_cycles = n;
    t.material[m].dosing_jiffies = 100 * n;
    t.material[m].after_sequence = n / 2;
  }
  return t;
}

std::uint32_t loaded_generation(firmware::TotalizerSlots& slots) {
  firmware::MaterialTotals t;
  if (!slots.load(t)) return 0;
  const firmware::MaterialTotals expected = totals_generation(t.material[0].gate_cycles);
  for (std::size_t m = 0; m < firmware::MaterialTable::kMaterials; ++m) {
    const firmware::Totalizers &a = t.material[m], &b = expected.material[m];
    if (a.total_g != b.total_g || a.fills != b.fills || a.valve_cycles != b.valve_cycles ||
        a.dosing_jiffies != b.dosing_jiffies || a.after_sequence != b.after_sequence) {
      return 0xFFFFFFFFu;  // a mixture of two generations
    }
  }
  return t.material[0].gate_cycles;
}

TEST(TotalizerSlots, AWriteCutAtEveryByteKeepsThePreviousTotals) {
  constexpr std::size_t kOffset = 100;  // behind other records, as in the --nvm file
  for (auto medium : {hal::host::CuttableNvm::Medium::eeprom, hal::host::CuttableNvm::Medium::flash}) {
    hal::host::CuttableNvm nvm(kOffset + firmware::kTotalizerSlotsBytes, medium);
    firmware::TotalizerSlots slots(nvm, kOffset);
    ASSERT_TRUE(slots.save(totals_generation(1)));
    std::uint32_t completed = 1;
    for (std::size_t cut = 0; cut < firmware::kTotalizerSlotSize; ++cut) {
      nvm.arm_cut(cut, std::uint8_t(cut));
      EXPECT_FALSE(slots.save(totals_generation(completed + 1)));
      firmware::TotalizerSlots restarted(nvm, kOffset);
      const std::uint32_t loaded = loaded_generation(restarted);
      EXPECT_TRUE(loaded == completed || loaded == completed + 1) << "cut " << cut << " loaded " << loaded;
      ASSERT_TRUE(restarted.save(totals_generation(loaded + 1))) << cut;
      completed = loaded + 1;
      EXPECT_EQ(loaded_generation(restarted), completed);
      slots.load(*std::make_unique<firmware::MaterialTotals>());  // the writer finds the newest again
    }
  }
}

}  // namespace
}  // namespace dynweigh::testing
