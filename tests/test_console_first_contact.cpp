// The console as a filling line, a terminal and a slow UART meet it: doses back to back,
// no weight from no sample, every answer whole at 115 bytes a jiffy, line editing and echo, and a
// jiffy that belongs to the board.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "dynweigh/firmware/console_line_reader.hpp"
#include "dynweigh/hal/host/simulated_plant_ports.hpp"
#include "support/console_session.hpp"
#include "support/string_console.hpp"

namespace dynweigh::testing {
namespace {

std::size_t final_answers(const std::string& output) {
  std::size_t n = 0;
  for (const std::string& line : lines_of(output)) n += (line == "OK" || line.rfind("ERR ", 0) == 0) ? 1 : 0;
  return n;
}

// Types the line and runs until its final answer, as a PLC or `dynweigh term --send` does: the
// next line goes as soon as this one's OK or ERR has come.
std::string answer_of(ConsoleSession& c, const std::string& line, std::uint32_t max_jiffies = 30000) {
  StringConsole console;
  console.pending = line + "\n";
  for (std::uint32_t i = 0; i < max_jiffies && !ends_with_answer(console.output); ++i) c.session().step(console);
  return console.output;
}

// Before: the dose's 1000-jiffy recording kept the indicator busy after the RESULT, and the next
// dose was refused `ERR 3 busy` for up to 9 s.
TEST(BackToBackDoses, TenDosesOneAfterTheOtherAreNoneRefused) {
  ConsoleSession c;
  for (int i = 1; i <= 10; ++i) {
    const std::string answer = answer_of(c, "dose 800");
    EXPECT_EQ(answer.rfind("RESULT target=800 ", 0), 0u) << "dose " << i << ": " << answer;
    EXPECT_EQ(lines_of(answer).back(), "OK") << "dose " << i;
  }
  // The recorder holds the last dose's first jiffies; `readtestdata info` says which.
  EXPECT_EQ(field(lines_of(answer_of(c, "readtestdata info"))[0], "dose"), "10");
  const std::string records = answer_of(c, "readtestdata");  // waits for the recording to end
  EXPECT_EQ(lines_of(records).size(), 1001u);
  EXPECT_EQ(lines_of(records).back(), "OK");
  EXPECT_EQ(answer_of(c, "readtestdata info"), "TESTDATA cycle=dose dose=10 target=800 strategy=model records=1000\nOK\n");
  EXPECT_EQ(answer_of(c, "starttestdata"), "OK\n");
  EXPECT_EQ(lines_of(answer_of(c, "readtestdata info"))[0].rfind("TESTDATA cycle=starttestdata records=", 0), 0u);
}

firmware::Inputs no_sample_yet() {
  firmware::Inputs in;
  in.load_cell.fresh = false;
  in.load_cell.raw_counts = 0;
  return in;
}

std::string typed(firmware::Indicator& indicator, firmware::Inputs in, const std::string& line) {
  in.console_rx = line.data();
  in.console_rx_length = line.size();
  indicator.step(in);
  std::string out;
  char buffer[256];
  for (std::size_t n; (n = indicator.drain_console(buffer, sizeof buffer)) > 0;) out.append(buffer, n);
  return out;
}

// Before: `status` showed weight=-12000 (no counts minus the zero) before the first sample.
TEST(NoSampleNoWeight, StatusAndTheStatusFrameShowNoWeightBeforeTheFirstSampleAndWhileStale) {
  sim::Plant plant(sim::default_scene(), 1);
  firmware::Indicator indicator(hal::host::factory_settings(plant));
  firmware::Inputs in = no_sample_yet();
  EXPECT_EQ(indicator.step(in).weight_100mg, firmware::kWeightUnknown100mg);
  EXPECT_EQ(typed(indicator, in, "status\n"), "STATUS state=idle weight=none valve=0 fault=none\nOK\n");

  in.load_cell.fresh = true;
  in.load_cell.raw_counts = 12000 + 250;  // the empty container and 250 g
  for (int i = 0; i < 300; ++i) indicator.step(in);
  EXPECT_EQ(indicator.step(in).weight_100mg, 2500);
  EXPECT_EQ(typed(indicator, in, "status\n"), "STATUS state=idle weight=250 valve=0 fault=none\nOK\n");

  in.load_cell.fresh = false;  // the samples stop: after the stale limit, no weight
  for (int i = 0; i < 20; ++i) indicator.step(in);
  EXPECT_EQ(indicator.step(in).weight_100mg, firmware::kWeightUnknown100mg);
  EXPECT_EQ(field(lines_of(typed(indicator, in, "status\n"))[0], "weight"), "none");
}

// The indicator on the default plant with the console drained at 115 bytes a jiffy (115200 baud
// on the Cortex-M UART, 10 ms jiffies).
class SlowUart {
 public:
  static constexpr std::size_t kBytesPerJiffy = 115;
  explicit SlowUart(std::size_t drain_per_jiffy = kBytesPerJiffy)
      : plant_(sim::default_scene(), 1), cell_(plant_), valve_(plant_, 0.01),
        indicator_(hal::host::factory_settings(plant_)), drain_(drain_per_jiffy) {}

  // Sends the lines in one burst and runs until the indicator is idle and everything has drained.
  std::string burst(const std::string& lines, std::uint32_t max_jiffies = 40000) {
    output_.clear();
    step(lines);
    for (std::uint32_t i = 0; i < max_jiffies && (indicator_.busy() || !drained_); ++i) step("");
    return output_;
  }

 private:
  void step(const std::string& typed) {
    firmware::Inputs in;
    in.load_cell = cell_.read_sample();
    in.valve_position = valve_.position();
    in.console_rx = typed.data();
    in.console_rx_length = typed.size();
    const firmware::Outputs out = indicator_.step(in);
    valve_.command(out.valve, out.valve_delay_100us);
    char buffer[512];
    std::size_t drained = 0;
    for (std::size_t n = 1; n > 0 && drained < drain_; drained += n) {
      n = indicator_.drain_console(buffer, std::min(sizeof buffer, drain_ - drained));
      output_.append(buffer, n);
    }
    drained_ = drained < drain_;
    plant_.advance(0.01);
  }

  sim::Plant plant_;
  hal::host::SimulatedLoadCell cell_;
  hal::host::SimulatedValve valve_;
  firmware::Indicator indicator_;
  std::size_t drain_;
  std::string output_;
  bool drained_ = true;
};

// Before: answers went into the 4096-byte ring once 1500 bytes were free, but `param` answers about
// 2 kB: the third of three `param` lines lost bytes and its OK.
TEST(SlowConsole, EveryCommandThreeTimesInABurstGetsThreeWholeAnswersAt115BytesAJiffy) {
  const std::vector<std::string> deterministic = {"param", "help", "version", "learn", "param fall_mm",
                                                  "readtestdata info", "bogus", "param jiffy_ms 20", "estimates"};
  SlowUart slow;
  SlowUart fast(100000);
  for (const std::string& command : deterministic) {
    const std::string once = fast.burst(command + "\n");
    const std::string thrice = slow.burst(command + "\n" + command + "\n" + command + "\n");
    EXPECT_EQ(thrice, once + once + once) << command;
  }
  for (const std::string command : {"status", "starttestdata 10 60", "readtestdata", "dose 500", "tare", "valve 0",
                                     "clearfault", "param fall_mm 1200", "zero", "cal 1000", "learn reset"}) {
    const std::string thrice = slow.burst(command + "\n" + command + "\n" + command + "\n");
    EXPECT_EQ(final_answers(thrice), 3u) << command << ":\n" << thrice.substr(0, 2000);
    EXPECT_TRUE(ends_with_answer(thrice)) << command;
  }
  // Three full `param` listings back to back, each whole.
  const std::string listings = slow.burst("param\nparam\nparam\n");
  EXPECT_EQ(lines_of(listings).size(), 3 * (firmware::kParameterCount + 1));
}

std::vector<std::string> lines_read(const std::string& bytes) {
  firmware::ConsoleLineReader reader;
  std::vector<std::string> lines;
  for (const char c : bytes) {
    if (reader.feed(c) == firmware::ConsoleLineReader::Event::line) lines.emplace_back(reader.line());
  }
  return lines;
}

std::string echoed(const std::string& bytes) {
  firmware::ConsoleLineReader reader;
  std::string echo;
  for (const char c : bytes) {
    reader.feed(c);
    echo += reader.echo();
  }
  return echo;
}

// Before: `statx<DEL>us` was the unknown command "statx\x7fus".
TEST(LineEditing, BackspaceAndDeleteEraseTheLastCharacterTyped) {
  EXPECT_EQ(lines_read("statx\x7fus\n"), std::vector<std::string>{"status"});
  EXPECT_EQ(lines_read("statx\bus\r\n"), std::vector<std::string>{"status"});
  EXPECT_EQ(lines_read("\b\x7fversion\n"), std::vector<std::string>{"version"});  // nothing to erase
  EXPECT_EQ(lines_read("dose 1000\b\b\b\b\b\b\b\b\b\bversion\n"), std::vector<std::string>{"version"});
  EXPECT_TRUE(lines_read("x\b\n").empty());  // erased to nothing: an empty line, ignored
  // A line already too long stays discarded whatever is erased afterwards.
  firmware::ConsoleLineReader reader;
  for (int i = 0; i < 90; ++i) reader.feed('x');
  for (int i = 0; i < 20; ++i) reader.feed('\x7f');
  EXPECT_EQ(reader.feed('\n'), firmware::ConsoleLineReader::Event::too_long);
}

TEST(LineEditing, EchoShowsTheCharactersErasuresAndOneNewlineForCrLf) {
  EXPECT_EQ(echoed("statx\x7fus\r\n"), "statx\b \bus\n");
  EXPECT_EQ(echoed("\bab\b\b\bc\n"), "ab\b \b\b \bc\n");
  EXPECT_EQ(echoed("a\rb\n"), "a\nb\n");
}

TEST(LineEditing, TheIndicatorEchoesOnlyWithParamEcho1) {
  ConsoleSession c;
  EXPECT_EQ(c.send_raw("statx\x7fus\n"), "STATUS state=idle weight=0 valve=0 fault=none\nOK\n");
  EXPECT_EQ(c.send_raw("param echo 1\n"), "echo=1\nOK\n");
  EXPECT_EQ(c.send_raw("statx\x7fus\r\n"), "statx\b \bus\nSTATUS state=idle weight=0 valve=0 fault=none\nOK\n");
  EXPECT_EQ(c.send_raw("param echo 0\n"), "param echo 0\necho=0\nOK\n");
  EXPECT_EQ(c.send_raw("version\n"), std::string("dynweigh ") + firmware::kFirmwareVersion + "\nOK\n");
}

// Before: `param jiffy_ms 20` was accepted on a board whose jiffy is 10 ms, and the next dose faulted.
TEST(OneJiffy, JiffyMsIsReadOnlyAndAStoredOtherValueLoadsAsTheBoards) {
  ConsoleSession c;
  EXPECT_EQ(c.run({"param jiffy_ms 20"}), "ERR 2 read-only\n");
  EXPECT_EQ(c.run({"param jiffy_ms"}), "jiffy_ms=10\nOK\n");
  EXPECT_NE(c.run({"param"}).find("jiffy_ms=10  # "), std::string::npos);

  firmware::PersistentSettings older;  // as an older firmware stored it
  older.parameters.raw()[static_cast<std::size_t>(firmware::ParameterId::jiffy_ms)] = 20.0f;
  older.parameters.set(firmware::ParameterId::fall_mm, 1500.0f);
  std::uint8_t record[firmware::kSettingsRecordSize];
  ASSERT_EQ(firmware::encode_settings(older, record, sizeof record), sizeof record);
  firmware::PersistentSettings loaded;
  ASSERT_TRUE(firmware::decode_settings(record, sizeof record, loaded));
  EXPECT_EQ(loaded.parameters.get(firmware::ParameterId::jiffy_ms), 10.0f);
  EXPECT_EQ(loaded.parameters.get(firmware::ParameterId::fall_mm), 1500.0f);
}

}  // namespace
}  // namespace dynweigh::testing
