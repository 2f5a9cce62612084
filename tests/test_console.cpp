// Every command and every error code of docs/console.md, through the same step function the firmware runs.
#include <gtest/gtest.h>

#include "support/console_session.hpp"

namespace dynweigh::testing {
namespace {

constexpr const char* kAdjustmentNote = "NOTE adjustment: new zero; no span until cal <grams> with a test weight\n";

std::string last_line(const std::string& output) {
  const auto lines = lines_of(output);
  return lines.empty() ? "" : lines.back();
}

TEST(Console, UnknownCommandIsErr1) {
  ConsoleSession c;
  EXPECT_EQ(c.run({"frobnicate"}), "ERR 1 unknown command\n");
  EXPECT_EQ(c.run({"STATUS"}), "ERR 1 unknown command\n");  // case-sensitive
}

TEST(Console, OverLongLineIsDiscardedWholeAndAnsweredErr2) {
  ConsoleSession c;
  const std::string long_line = "status " + std::string(100, 'x') + "\n";
  EXPECT_EQ(c.send_raw(long_line), "ERR 2 line too long\n");
  // An 80-character line is still a line: an unknown command, not too long.
  EXPECT_EQ(c.send_raw(std::string(80, 'a') + "\n"), "ERR 1 unknown command\n");
  // And the console still works afterwards.
  EXPECT_EQ(last_line(c.send_raw("version\n")), "OK");
}

TEST(Console, LineEndingsCrLfAndCrLfAndEmptyLines) {
  ConsoleSession c;
  const std::string out = c.send_raw("version\r\n\r\n\nversion\rversion\n", 5);
  EXPECT_EQ(lines_of(out).size(), 6u) << out;  // three answers of two lines, nothing for empty lines
}

TEST(Console, StatusReportsIdleWeightValveAndFault) {
  ConsoleSession c;
  const auto lines = lines_of(c.run({"status"}));
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0], "STATUS state=idle weight=0 valve=0 fault=none");
  EXPECT_EQ(lines[1], "OK");
}

TEST(Console, HelpListsEveryCommandAndVersionNamesTheFirmware) {
  ConsoleSession c;
  const std::string help = c.run({"help"});
  for (const char* name : {"starttestdata", "readtestdata", "dose", "tare", "zero", "cal", "status", "param",
                           "valve", "clearfault", "help", "version"}) {
    EXPECT_NE(("\n" + help).find("\n" + std::string(name) + " "), std::string::npos) << name;
  }
  EXPECT_EQ(last_line(help), "OK");
  EXPECT_EQ(c.run({"version"}), std::string("dynweigh ") + firmware::kFirmwareVersion + "\nOK\n");
}

TEST(Console, StartTestDataRejectsBadRangesWithErr2) {
  ConsoleSession c;
  for (const char* bad : {"starttestdata 600 50", "starttestdata 0 1001", "starttestdata -1 5",
                          "starttestdata 5", "starttestdata a b", "starttestdata 1 2 3", "starttestdata 5x 10"}) {
    EXPECT_EQ(last_line(c.run({bad})).rfind("ERR 2", 0), 0u) << bad;
  }
}

TEST(Console, ReadTestDataBeforeAnyCycleIsErr2NoTestData) {
  ConsoleSession c;
  EXPECT_EQ(c.run({"readtestdata"}), "ERR 2 no test data\n");
}

TEST(Console, CommandsDuringACycleAreErr3Busy) {
  ConsoleSession c;
  EXPECT_EQ(c.send_raw("starttestdata 0 1000\n", 1), "OK\n");
  for (const char* cmd : {"readtestdata", "dose 100", "tare", "zero", "cal 1000", "valve 2", "starttestdata",
                          "param fall_mm 1000"}) {
    EXPECT_EQ(c.send_raw(std::string(cmd) + "\n", 1), "ERR 3 busy\n") << cmd;
  }
  // Reading is always allowed.
  EXPECT_EQ(c.send_raw("status\n", 1).rfind("STATUS state=dosing", 0), 0u);
  EXPECT_EQ(c.send_raw("param fall_mm\n", 1), "fall_mm=1200\nOK\n");
}

TEST(Console, DoseArgumentsOutOfRangeAreErr2) {
  ConsoleSession c;
  for (const char* bad : {"dose", "dose 0", "dose -5", "dose 50001", "dose 12.5", "dose 100 fastest",
                          "dose 100 model extra"}) {
    EXPECT_EQ(last_line(c.run({bad})).rfind("ERR 2", 0), 0u) << bad;
  }
}

TEST(Console, FaultIsErr4AndLatchedUntilCleared) {
  ConsoleSession c;
  // A sample flagged as an ADC error raises a latched fault.
  struct FaultyCell final : hal::LoadCellPort {
    firmware::LoadCellInput read_sample() override {
      firmware::LoadCellInput in;
      in.raw_counts = 12000;
      in.status = firmware::kLoadCellAdcError;
      return in;
    }
  } cell;
  struct Valve final : hal::ValvePort {
    void command(firmware::ValveCommand c, std::uint8_t) override { last = c; }
    firmware::ValvePosition position() const override { return firmware::ValvePosition::closed; }
    firmware::ValveCommand last = firmware::ValveCommand::open;
  } valve;
  struct Silent final : hal::ConsolePort {
    std::size_t read(char*, std::size_t) override { return 0; }
    void write(const char*, std::size_t) override {}
  } silent;
  hal::Ports ports{cell, valve, silent, nullptr};
  firmware::Indicator& indicator = c.session().indicator();
  hal::run_one_jiffy(indicator, ports, 0);
  EXPECT_EQ(valve.last, firmware::ValveCommand::closed);
  EXPECT_EQ(c.run({"status"}), "STATUS state=fault weight=0 valve=0 fault=adc_error\nOK\n");
  EXPECT_EQ(c.run({"dose 1000"}), "ERR 4 fault active\n");
  EXPECT_EQ(c.run({"valve 2"}), "ERR 4 fault active\n");
  EXPECT_EQ(c.run({"clearfault"}), "OK\n");
  EXPECT_EQ(lines_of(c.run({"status"}))[0], "STATUS state=idle weight=0 valve=0 fault=none");
}

TEST(Console, UncalibratedIndicatorAnswersErr5) {
  firmware::PersistentSettings blank;  // no calibration: a new board
  ConsoleSession c(sim::default_scene(), 1, blank);
  EXPECT_EQ(c.run({"dose 1000"}), "ERR 5 not calibrated\n");
  EXPECT_EQ(c.run({"tare"}), "ERR 5 not calibrated\n");
  EXPECT_EQ(c.run({"cal 1000"}), "ERR 5 zero the empty scale first\n");
}

TEST(Console, ZeroThenCalWithAKnownLoadCalibrates) {
  firmware::PersistentSettings blank;
  ConsoleSession c(sim::default_scene(), 1, blank);
  c.idle(100);  // let the filter settle on the empty scale
  // No span yet: the zero is an adjustment, and the answer says what comes next.
  EXPECT_EQ(c.run({"zero"}), std::string(kAdjustmentNote) + "OK\n");
  EXPECT_EQ(c.run({"cal 1000"}), "ERR 2 load too small to calibrate\n");
  // Put a known load on the scale: run the valve open, then let everything land and settle.
  EXPECT_EQ(c.run({"valve 2"}), "OK\n");
  c.idle(150);
  EXPECT_EQ(c.run({"valve 0"}), "OK\n");
  c.idle(1500);
  const double truth_g = c.session().plant().truth().static_kg * 1000.0;
  const long load = std::lround(truth_g);
  EXPECT_EQ(c.run({"cal " + std::to_string(load)}), "OK\n");
  const auto status = lines_of(c.run({"status"}))[0];
  EXPECT_NEAR(std::stod(field(status, "weight")), truth_g, 1.0) << status;
  EXPECT_TRUE(c.session().indicator().settings().calibration.valid());
}

TEST(Console, TareZeroesTheDisplayedWeight) {
  ConsoleSession c;
  c.run({"valve 2"});
  c.idle(100);
  c.run({"valve 0"});
  c.idle(1500);
  EXPECT_GT(std::stoi(field(lines_of(c.run({"status"}))[0], "weight")), 500);
  EXPECT_EQ(c.run({"tare"}), "OK\n");
  EXPECT_NEAR(std::stoi(field(lines_of(c.run({"status"}))[0], "weight")), 0, 1);
}

// OIML R76: 4 % of Max is the range of zero-setting in use; beyond it `zero` is an adjustment, which
// sets the zero anywhere and leaves the scale without a span until `cal`.
TEST(Console, ZeroOutsideTheZeroRangeIsAnAdjustmentThatAsksForCal) {
  ConsoleSession c;
  c.run({"valve 2"});
  c.idle(150);  // about 2.4 kg: beyond 4 % of 50 kg
  c.run({"valve 0"});
  c.idle(600);
  EXPECT_EQ(c.run({"zero"}), std::string(kAdjustmentNote) + "OK\n");
  EXPECT_EQ(c.run({"dose 1000"}), "ERR 5 not calibrated\n");
  EXPECT_EQ(c.run({"status"}), "STATUS state=idle weight=none valve=0 fault=none\nOK\n");
}

TEST(Console, ParamListsReadsSetsAndRejects) {
  ConsoleSession c;
  const std::string list = c.run({"param"});
  for (const char* name : {"bore_mm=60", "fall_mm=1200", "container_mm=300", "density=1550", "capacity_g=50000",
                           "jiffy_ms=10", "filter=iir"}) {
    EXPECT_NE(list.find(name), std::string::npos) << name;
  }
  EXPECT_EQ(c.run({"param fall_mm 1500"}), "fall_mm=1500\nOK\n");
  EXPECT_EQ(c.run({"param fall_mm"}), "fall_mm=1500\nOK\n");
  EXPECT_EQ(c.run({"param filter avg"}), "filter=avg\nOK\n");
  EXPECT_EQ(c.run({"param density 1234.5"}), "density=1234.5\nOK\n");
  EXPECT_EQ(c.run({"param nosuch"}), "ERR 2 unknown parameter\n");
  EXPECT_EQ(c.run({"param fall_mm 0"}), "ERR 2 value out of range\n");
  EXPECT_EQ(c.run({"param fall_mm 1e3"}), "ERR 2 not a number\n");
  EXPECT_EQ(c.run({"param filter kalman"}), "ERR 2 value out of range\n");
  EXPECT_EQ(c.run({"param fall_mm"}), "fall_mm=1500\nOK\n");  // unchanged by the rejects
}

TEST(Console, ParametersAndCalibrationSurviveARestart) {
  ConsoleSession first;
  first.run({"param fall_mm 1500"});
  const firmware::PersistentSettings saved = first.session().indicator().settings();
  std::uint8_t record[firmware::kSettingsRecordSize];
  ASSERT_EQ(firmware::encode_settings(saved, record, sizeof record), sizeof record);
  firmware::PersistentSettings restored;
  ASSERT_TRUE(firmware::decode_settings(record, sizeof record, restored));
  ConsoleSession second(sim::default_scene(), 1, restored);
  EXPECT_EQ(second.run({"param fall_mm"}), "fall_mm=1500\nOK\n");
}

TEST(Console, ManualValveOpensAndClosesWhenIdleAndRejectsBadPositions) {
  ConsoleSession c;
  EXPECT_EQ(c.run({"valve 2"}), "OK\n");
  EXPECT_EQ(field(lines_of(c.run({"status"}))[0], "valve"), "2");
  EXPECT_EQ(c.run({"valve 3"}), "ERR 2 usage: valve <0|1|2>\n");
  EXPECT_EQ(c.run({"valve"}), "ERR 2 usage: valve <0|1|2>\n");
  EXPECT_EQ(c.run({"valve 0"}), "OK\n");
  EXPECT_EQ(field(lines_of(c.run({"status"}))[0], "valve"), "0");
}

}  // namespace
}  // namespace dynweigh::testing
