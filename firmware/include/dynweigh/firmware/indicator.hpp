#pragma once
// The weigh indicator as a pure step function: one call per jiffy with that
// jiffy's Inputs, returning its Outputs. No hardware, no clock, no heap, no blocking; the console's
// answers accumulate in a transmit ring that the board drains at its own pace.
#include <cstddef>
#include <cstdint>

#include "dynweigh/firmware/console_line_reader.hpp"
#include "dynweigh/firmware/display_filter.hpp"
#include "dynweigh/firmware/dosing_cycle.hpp"
#include "dynweigh/firmware/fault.hpp"
#include "dynweigh/firmware/fault_supervisor.hpp"
#include "dynweigh/firmware/io.hpp"
#include "dynweigh/firmware/logbook.hpp"
#include "dynweigh/firmware/persistent_settings.hpp"
#include "dynweigh/firmware/standstill_average.hpp"
#include "dynweigh/firmware/test_data_recorder.hpp"
#include "dynweigh/firmware/text_writer.hpp"
#include "dynweigh/firmware/tolerance_follow_up.hpp"
#include "dynweigh/firmware/totalizers.hpp"

namespace dynweigh::firmware {

inline constexpr const char* kFirmwareVersion = "0.1.0";

class Indicator {
 public:
  explicit Indicator(const PersistentSettings& settings);

  Outputs step(const Inputs& inputs);
  std::size_t drain_console(char* destination, std::size_t capacity) {
    return console_.drain(destination, capacity);
  }

  const PersistentSettings& settings() const { return settings_; }
  // The board's logbook (opened): every certified result is appended to it, numbered on from its
  // newest record. Without one the results are still numbered (a replay's indicator, started where
  // the recorded one was with resume_sequence), and `log` and `stats` have nothing to show.
  void attach_logbook(Logbook* logbook) {
    logbook_ = logbook;
    last_sequence_ = logbook ? logbook->last_sequence() : 0;
  }
  void resume_sequence(std::uint32_t last) { last_sequence_ = last; }
  std::uint32_t last_sequence() const { return last_sequence_; }
  float filtered_weight_g() const;
  // A weight can be shown: calibrated, and a sample has come and is not stale.
  bool weight_known() const;
  float last_prediction_g() const { return dosing_.last_prediction_g(); }
  Fault fault() const { return fault_; }
  const FaultSupervisor& supervisor() const { return supervisor_; }
  // A command is still running or queued: a scripted console waits before sending the next line.
  bool busy() const;

  // The longest answer a command writes at once (the `param` listing; `help` and `learn` are checked
  // against it where they are written). The console ring keeps room for it before a command runs.
  static constexpr std::size_t kLongestAnswerBytes = kParameterListingMaxBytes;

  // The console's commands; public so the command table can name them.
  struct Arguments {
    static constexpr std::size_t kMax = 4;
    const char* word[kMax];
    std::size_t count;
  };
  void command_starttestdata(const Arguments& args);
  void command_readtestdata(const Arguments& args);
  void command_dose(const Arguments& args);
  void command_tare(const Arguments& args);
  void command_zero(const Arguments& args);
  void command_cal(const Arguments& args);
  void command_status(const Arguments& args);
  void command_param(const Arguments& args);
  void command_valve(const Arguments& args);
  void command_clearfault(const Arguments& args);
  void command_abort(const Arguments& args);
  void command_learn(const Arguments& args);
  void command_estimates(const Arguments& args);
  void command_accept(const Arguments& args);
  void command_topup(const Arguments& args);
  void command_log(const Arguments& args);
  void command_stats(const Arguments& args);
  void command_help(const Arguments& args);
  void command_version(const Arguments& args);

 private:
  struct QueuedLine {
    char text[ConsoleLineReader::kMaxLine + 1];
    bool too_long;
  };
  struct TestCycle {
    bool active = false;
    bool scheduled = false;
    std::uint32_t jiffy = 0;
    std::uint32_t open_jiffy = 0;
    std::uint32_t close_jiffy = 0;
  };
  // What the test-data recorder holds: a test cycle, or which dose.
  struct RecordingSource {
    bool dose = false;
    std::uint32_t dose_number = 0;  // doses started since power-up, the first is 1
    std::int32_t target_g = 0;
    DosingStrategy strategy = DosingStrategy::model;
  };
  // `zero` or `cal` waiting for standstill.
  struct Adjustment {
    enum class Kind : std::uint8_t { none, zero, span } kind = Kind::none;
    std::int32_t grams = 0;
    std::uint32_t jiffies = 0;
  };

  void receive_console(const Inputs& inputs);
  void report_telemetry(Outputs& out) const;
  void execute_queued_commands();
  void execute(char* line);
  void process_sample(const LoadCellInput& sample);
  void raise(Fault fault);
  void supervise(const Inputs& inputs);
  void advance_dose();
  // The certified result judged against its tolerance: reported, topped up or held (fill_conclusion.cpp).
  void conclude_dose();
  void advance_follow_up();
  void judge_result();
  void report_result();
  void report_hold();
  void write_fill_line_start(const char* tag);
  void write_verdict_fields();
  ValveCommand advance_test_cycle();
  void continue_print();
  void continue_log_print();
  void apply_parameters();
  void echo_typed(const char* text);
  void start_adjustment(Adjustment::Kind kind, std::int32_t grams);
  void advance_adjustment(bool fresh_sample);
  void finish_zero();
  void finish_span();
  // Counts relative to reference_counts_: the float domain the filter and the dose work in.
  float relative_counts(std::int32_t raw) const { return float(std::int64_t(raw) - reference_counts_); }
  // The calibrated zero in those counts (its fraction alone once rebased to it).
  float zero_relative_counts() const {
    return relative_counts(settings_.calibration.zero_counts) + settings_.calibration.zero_fraction;
  }
  void rebase_to_zero();

  // A load cell of 1 count per kg under a 10 kg test weight still has a span (10 counts); fewer than
  // a handful of counts is no load at all. Under kCoarseSpanCounts the answer warns of the resolution.
  static constexpr float kMinimumSpanCounts = 5.0f;
  static constexpr float kCoarseSpanCounts = 100.0f;
  bool cycle_running() const;
  bool reject_if_busy();
  // A command that changed the settings answers once the board has said whether it saved them.
  void ok() {
    if (settings_changed_) {
      ++answers_after_save_;
    } else {
      console_.line("OK");
    }
  }
  void answer_after_save(SettingsSave report);
  void error(int code, const char* text);

  PersistentSettings settings_;
  bool settings_changed_ = false;
  std::uint8_t answers_after_save_ = 0;  // OKs held until the board reports the save
  ConsoleLineReader reader_;
  static constexpr std::size_t kQueue = 4;
  QueuedLine queue_[kQueue];
  std::size_t queue_head_ = 0, queue_count_ = 0;
  TextWriter console_;

  DisplayFilter filter_;
  std::int32_t reference_counts_ = 0;  // the calibrated zero's whole counts, or the first sample
  bool has_reference_ = false;
  std::int32_t raw_sample_ = 0;        // the last fresh sample as it came
  float filtered_counts_ = 0.0f;
  float raw_counts_ = 0.0f;
  bool has_sample_ = false;
  float tare_g_ = 0.0f;
  std::uint32_t stale_jiffies_ = 0;
  std::uint32_t silent_jiffies_ = 0;  // of those, jiffies the link reported silent
  std::uint16_t last_counter_ = 0;
  Fault fault_ = Fault::none;
  FaultSupervisor supervisor_;
  float screened_counts_ = 0.0f;  // the sample the filter and the dose use (outliers held out)

  DosingCycle dosing_;
  ToleranceFollowUp follow_up_;
  DoseResult concluding_;  // the certified result being judged, topped up or held
  ToleranceVerdict verdict_ = ToleranceVerdict::ok;
  Logbook* logbook_ = nullptr;
  std::uint32_t last_sequence_ = 0;  // the last result's number
  struct LogPrint {
    bool active = false;
    std::uint32_t next = 0, last = 0;  // sequence numbers still to print
  } log_print_;
  std::uint32_t jiffy_ = 0;  // the board's jiffy count, for the logbook
  Totalizers totals_;
  bool dose_command_pending_ = false;  // `dose` answers when it ends
  TestCycle test_;
  TestDataRecorder recorder_;
  RecordingSource recording_source_;
  std::uint32_t doses_started_ = 0;
  Adjustment adjustment_;
  StandstillAverage standstill_;
  bool printing_ = false;
  std::size_t print_index_ = 0;
  ValveCommand manual_valve_ = ValveCommand::closed;
  ValveCommand valve_ = ValveCommand::closed;
  std::uint8_t valve_delay_100us_ = 0;  // how far into its jiffy valve_ acts
};

}  // namespace dynweigh::firmware
