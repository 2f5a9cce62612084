#pragma once
// The weigh indicator as a pure step function: one call per jiffy with that jiffy's Inputs,
// returning its Outputs. No hardware, no clock, no heap, no blocking; the console's answers
// accumulate in a transmit ring that the board drains at its own pace.
//
// A jiffy runs six stages, in this order (step() reads so): sense (the console's bytes, the load
// cell's sample on the scale), supervise (every fault; a fault closes the valve in this very jiffy),
// command (the queued console lines, a zero or span waiting for standstill), dose (the dosing cycle
// and what follows its result, the discharge), actuate (the valve and gate commands in force) and report (the recorder, the
// listings being printed, the Outputs). The parts: the console (console.hpp, the commands in
// console_commands.cpp and the *_commands.cpp beside it), the scale (scale.hpp), the fault
// supervisor (fault_supervisor.hpp), the dosing cycle (dosing_cycle.hpp) and its tolerance
// follow-up (tolerance_follow_up.hpp), the discharge cycle (discharge_cycle.hpp).
#include <cstddef>
#include <cstdint>

#include "dynweigh/firmware/batch_cycle.hpp"
#include "dynweigh/firmware/console.hpp"
#include "dynweigh/firmware/discharge_cycle.hpp"
#include "dynweigh/firmware/dosing_cycle.hpp"
#include "dynweigh/firmware/fault.hpp"
#include "dynweigh/firmware/fault_supervisor.hpp"
#include "dynweigh/firmware/io.hpp"
#include "dynweigh/firmware/logbook.hpp"
#include "dynweigh/firmware/persistent_settings.hpp"
#include "dynweigh/firmware/scale.hpp"
#include "dynweigh/firmware/test_data_recorder.hpp"
#include "dynweigh/firmware/tolerance.hpp"
#include "dynweigh/firmware/tolerance_follow_up.hpp"
#include "dynweigh/firmware/totalizers.hpp"

namespace dynweigh::firmware {

inline constexpr const char* kFirmwareVersion = "0.1.0";

struct ConsoleCommands;

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
  // The board's store of the totalizers (each material's): loaded now, written with each result.
  // Without one they count in RAM from start-up.
  void attach_totalizers(TotalizerSlots* store) {
    totalizer_store_ = store;
    if (store) store->load(totals_);
  }
  void resume_sequence(std::uint32_t last) { last_sequence_ = last; }
  std::uint32_t last_sequence() const { return last_sequence_; }
  float filtered_weight_g() const { return scale_.filtered_net_g(settings_.calibration); }
  // A weight can be shown: calibrated, and a sample has come and is not stale.
  bool weight_known() const;
  float last_prediction_g() const { return dosing_.last_prediction_g(); }
  Fault fault() const { return fault_; }
  // Whose valve the last Outputs' `valve` commanded: the board reads that one's feedback next.
  std::uint8_t valve_ingredient() const { return ingredient_; }
  const FaultSupervisor& supervisor() const { return supervisor_; }
  // A command is still running or queued: a scripted console waits before sending the next line.
  bool busy() const;

  // What the indicator is doing, as `status` names it; the Outputs' state shows `hold` as settling.
  enum class Activity : std::uint8_t { idle, dosing, settling, hold, fault, discharging };
  Activity activity() const;
  static const char* activity_name(Activity activity);
  static IndicatorState state_of(Activity activity);

  // The longest answer a command writes at once.
  static constexpr std::size_t kLongestAnswerBytes = Console::kLongestAnswerBytes;

 private:
  friend struct ConsoleCommands;  // the console's command handlers act on the parts below

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

  // The stages of a jiffy.
  void sense(const Inputs& inputs);
  void report_telemetry(Outputs& out) const;
  void supervise(const Inputs& inputs);
  void command(bool fresh_sample);
  void dose();
  void actuate();
  Outputs report(const Inputs& inputs);

  void apply_parameters();
  void raise(Fault fault);
  bool dose_running() const { return dosing_.phase() != DosingCycle::Phase::idle; }
  bool cycle_running() const;
  bool reject_if_busy();
  // A command that changed the settings answers once the board has said whether it saved them.
  void ok() {
    if (settings_changed_) {
      console_.hold_ok();
    } else {
      console_.line("OK");
    }
  }
  void answer_after_save(SettingsSave report);
  void run_queued_lines();
  // `zero` and `cal` answer once the reading stands still (scale_commands.cpp).
  void answer_adjustment(Scale::AdjustmentEnd end);
  void advance_dose();
  void learn_from_result();
  // The certified result judged against its tolerance: reported, topped up or held (fill_conclusion.cpp).
  void conclude_dose();
  void conclude_top_up();
  void start_top_up();
  void offer_sizing_reading(bool pulse_may_follow);
  float model_accepted_short_g() const;
  void keep_top_up_learning();
  void keep_valve_dead_time();
  void save_lessons();
  // A dose of `material`, by the console's `dose` or a batch's ingredient: what the material's
  // earlier doses taught restored, to the dosing cycle and to the valve's supervision.
  void start_dose(std::size_t material, std::int32_t target_g, DosingStrategy strategy);
  void judge_result();
  void report_result();
  void report_hold();
  void write_fill_line_start(const char* tag);
  void write_verdict_fields();
  ValveCommand advance_test_cycle();
  // The discharge and its answer (discharge_commands.cpp).
  void start_discharge();
  void advance_discharge();
  void continue_print();
  // A batch's ingredients, one dose each (batch_commands.cpp).
  void start_batch_ingredient();
  void select_material(std::size_t n);
  void use_valve(std::uint8_t ingredient);
  void end_batch(bool complete);
  void continue_log_print();

  PersistentSettings settings_;
  bool settings_changed_ = false;  // this jiffy: the board should save them
  // What a dose's fills and pulses taught, in the settings but not yet saved: saved once, when the
  // dose ends (its result reported or held, a fault, an abort), not after every pulse.
  bool lessons_unsaved_ = false;
  bool dose_valve_watched_ = false;  // a dose began: its valve's dead time is kept when it ends

  // The parts.
  Console console_;
  Scale scale_;
  FaultSupervisor supervisor_;
  Fault fault_ = Fault::none;  // latched until `clearfault`
  DosingCycle dosing_;
  ToleranceFollowUp follow_up_;
  DischargeCycle discharge_;
  BatchCycle batch_;
  DosingStrategy batch_strategy_ = DosingStrategy::model;

  // A dose's command and result.
  bool dose_command_pending_ = false;  // `dose` answers when it ends
  DoseResult concluding_;  // the certified result being judged, topped up or held
  ToleranceVerdict verdict_ = ToleranceVerdict::ok;
  std::uint32_t doses_started_ = 0;
  bool discharge_command_pending_ = false;  // `discharge` (or an auto-discharging `dose`) answers when it ends

  // The records: logbook, totalizers, test data.
  Logbook* logbook_ = nullptr;
  std::uint32_t last_sequence_ = 0;  // the last result's number
  std::uint32_t jiffy_ = 0;          // the board's jiffy count, for the logbook
  MaterialTotals totals_;
  TotalizerSlots* totalizer_store_ = nullptr;
  Totalizers& selected_totals() { return totals_.material[settings_.materials.selected()]; }
  bool save_totals() { return !totalizer_store_ || totalizer_store_->save(totals_); }
  TestCycle test_;
  TestDataRecorder recorder_;
  RecordingSource recording_source_;

  // Listings printed a few lines a jiffy as the console ring drains.
  bool printing_ = false;  // `readtestdata`
  std::size_t print_index_ = 0;
  struct LogPrint {
    bool active = false;
    std::uint32_t next = 0, last = 0;  // sequence numbers still to print
  } log_print_;

  // The valve.
  ValveCommand manual_valve_ = ValveCommand::closed;
  ValveCommand valve_ = ValveCommand::closed;
  std::uint8_t valve_delay_100us_ = 0;  // how far into its jiffy valve_ acts
  std::uint8_t ingredient_ = 0;          // whose valve valve_ commands (a batch's ingredient)
  std::uint8_t ingredient_valves_ = 1;   // this jiffy's Inputs: bit i, ingredient valve i is there
  GateCommand gate_ = GateCommand::closed;
  GatePosition gate_position_ = GatePosition::closed;  // this jiffy's feedback
};

}  // namespace dynweigh::firmware
