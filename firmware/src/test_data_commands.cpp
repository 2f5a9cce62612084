// The test data on the console (the thesis' indicator, its section 2.2): `starttestdata` runs a
// 1000-jiffy test cycle, `readtestdata` prints what the recorder holds (a test cycle, or a dose's
// first 1000 jiffies) a few lines a jiffy as the console ring drains.
#include <cstring>

#include "console_commands.hpp"

namespace dynweigh::firmware {

void ConsoleCommands::starttestdata(Indicator& indicator, const Arguments& args) {
  Console& console = indicator.console_;
  if (args.count != 1 && args.count != 3) return console.error(2, "usage: starttestdata [<open> <close>]");
  long open = 0, close = 0;
  if (args.count == 3 && (!parse_int(args.word[1], 0, 1000, open) || !parse_int(args.word[2], 0, 1000, close) ||
                          open > close)) {
    return console.error(2, "need 0 <= open <= close <= 1000");
  }
  if (indicator.reject_if_busy()) return;
  if (indicator.fault_ != Fault::none && args.count == 3) return console.error(4, "fault active");
  indicator.test_ = Indicator::TestCycle{true, args.count == 3, 0, std::uint32_t(open), std::uint32_t(close)};
  indicator.recorder_.start();
  indicator.recording_source_ = Indicator::RecordingSource{};
  indicator.ok();
}

void ConsoleCommands::readtestdata(Indicator& indicator, const Arguments& args) {
  Console& console = indicator.console_;
  const bool info = args.count == 2 && std::strcmp(args.word[1], "info") == 0;
  if (args.count != 1 && !info) return console.error(2, "usage: readtestdata [info]");
  if (info) {
    if (!indicator.recorder_.has_data()) return console.error(2, "no test data");
    console.write("TESTDATA cycle=");
    if (indicator.recording_source_.dose) {
      console.write("dose dose=");
      console.write_int(indicator.recording_source_.dose_number);
      console.write(" target=");
      console.write_int(indicator.recording_source_.target_g);
      console.write(" strategy=");
      console.write(strategy_name(indicator.recording_source_.strategy));
    } else {
      console.write("starttestdata");
    }
    console.write(" records=");
    console.write_int(std::int64_t(indicator.recorder_.count()));
    console.put('\n');
    return indicator.ok();
  }
  if (indicator.reject_if_busy()) return;
  if (!indicator.recorder_.has_data()) return console.error(2, "no test data");
  // A dose's recording still running after its result: the print waits for its 1000 records.
  indicator.printing_ = true;
  indicator.print_index_ = 0;
}

ValveCommand Indicator::advance_test_cycle() {
  if (!test_.active) return manual_valve_;
  ValveCommand valve = manual_valve_;
  if (test_.scheduled) {
    const bool open = test_.jiffy >= test_.open_jiffy && test_.jiffy < test_.close_jiffy;
    valve = open ? ValveCommand::open : ValveCommand::closed;
  }
  if (++test_.jiffy >= TestDataRecorder::kRecords) {
    test_.active = false;
    if (test_.scheduled) manual_valve_ = ValveCommand::closed;  // a scheduled cycle ends closed
  }
  return valve;
}

void Indicator::continue_print() {
  if (printing_ && recorder_.recording()) return;  // a dose's recording still runs: print it whole
  while (printing_ && console_.free_space() >= Console::kRoomForARecord) {
    if (print_index_ == TestDataRecorder::kRecords) {
      printing_ = false;
      ok();
      return;
    }
    const TestDataRecorder::Record r = recorder_.at(print_index_);
    console_.write_int(std::int64_t(print_index_));
    console_.put(' ');
    console_.write_int(r.raw_counts);
    console_.put(' ');
    console_.write_int(r.filtered_g);
    console_.put(' ');
    console_.write_int(r.marker);
    console_.put('\n');
    ++print_index_;
  }
}

}  // namespace dynweigh::firmware
