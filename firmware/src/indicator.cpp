#include "dynweigh/firmware/indicator.hpp"

#include <cmath>
#include <cstring>

namespace dynweigh::firmware {
namespace {
constexpr std::uint32_t kStaleLimitJiffies = DosingCycle::kBlindHorizonJiffies;  // 100 ms without a sample
// A command runs once its whole answer fits: the longest (a listing, sized at compile time beside
// the text it lists) and the answer a running command (dose, zero, cal) may still add to it.
constexpr std::size_t kRoomForARunningAnswer = 256;
constexpr std::size_t kRoomForAnAnswer = Indicator::kLongestAnswerBytes + kRoomForARunningAnswer;
constexpr std::size_t kRoomForARecord = 48;
static_assert(kRoomForAnAnswer + kRoomForARecord <= TextWriter::kCapacity,
              "the console ring cannot hold the longest answer: enlarge TextWriter::kCapacity");
constexpr float kOverloadMarginG = 9.0f;                // 9 d above Max, as OIML R76 blanks
}  // namespace

Indicator::Indicator(const PersistentSettings& settings) : settings_(settings) {
  if (settings_.calibration.zero_set) {
    reference_counts_ = settings_.calibration.zero_counts;
    has_reference_ = true;
  }
  apply_parameters();
}

void Indicator::apply_parameters() {
  const Parameters& p = settings_.parameters;
  filter_.configure(p.filter(), p.get(ParameterId::filter_hz), p.get(ParameterId::jiffy_ms) / 1000.0f);
  if (has_sample_) filter_.reset(filtered_counts_);  // otherwise the first sample primes it
  dosing_.configure(p);
  follow_up_.configure(p);
  supervisor_.configure(p);
}

float Indicator::filtered_weight_g() const {
  const Calibration& cal = settings_.calibration;
  if (!cal.valid()) return 0.0f;
  return (filtered_counts_ - zero_relative_counts()) / cal.counts_per_gram - tare_g_;
}

bool Indicator::weight_known() const {
  return has_sample_ && stale_jiffies_ < kStaleLimitJiffies && settings_.calibration.valid();
}

// A dose's test-data recording runs on after its result and is no part of it: the next dose
// restarts it (`readtestdata info` tells which dose the recorder holds).
bool Indicator::cycle_running() const {
  return dosing_.phase() != DosingCycle::Phase::idle || test_.active ||
         adjustment_.kind != Adjustment::Kind::none || follow_up_.active();
}

// A dose held for the operator waits on the console: a script may send `accept` or `topup`.
bool Indicator::busy() const {
  const bool holding = follow_up_.phase() == ToleranceFollowUp::Phase::holding;
  return queue_count_ > 0 || printing_ || log_print_.active || answers_after_save_ > 0 || (cycle_running() && !holding);
}

// Settings that did not reach the storage hold only until power is lost: a fault, not an OK.
void Indicator::answer_after_save(SettingsSave report) {
  if (report == SettingsSave::failed) raise(Fault::nvm_error);
  for (; answers_after_save_ > 0; --answers_after_save_) {
    if (report == SettingsSave::failed) {
      error(4, "fault nvm_error");
    } else {
      console_.line("OK");
    }
  }
}

void Indicator::error(int code, const char* text) {
  console_.write("ERR ");
  console_.write_int(code);
  console_.put(' ');
  console_.line(text);
}

bool Indicator::reject_if_busy() {
  if (!cycle_running()) return false;
  error(3, "busy");
  return true;
}

void Indicator::raise(Fault fault) {
  if (fault_ != Fault::none) return;  // the first cause is the one to report
  fault_ = fault;
  test_.scheduled = false;
  if (dosing_.phase() != DosingCycle::Phase::idle) dosing_.abort();
  follow_up_.finish();
  if (dose_command_pending_ || adjustment_.kind != Adjustment::Kind::none) {
    dose_command_pending_ = false;
    adjustment_.kind = Adjustment::Kind::none;
    console_.write("ERR 4 fault ");
    console_.line(fault_name(fault));
  }
}

Outputs Indicator::step(const Inputs& inputs) {
  settings_changed_ = false;
  jiffy_ = inputs.jiffy;
  answer_after_save(inputs.settings_save);
  receive_console(inputs);
  process_sample(inputs.load_cell);
  supervise(inputs);
  execute_queued_commands();
  advance_adjustment(inputs.load_cell.fresh);
  advance_dose();
  advance_follow_up();
  const ValveCommand scheduled = advance_test_cycle();
  const ValveCommand before = valve_;
  if (fault_ != Fault::none) {
    valve_ = ValveCommand::closed;
  } else if (dosing_.phase() != DosingCycle::Phase::idle) {
    valve_ = dosing_.valve();
  } else if (follow_up_.active()) {
    valve_ = follow_up_.valve();
  } else {
    valve_ = scheduled;
  }
  totals_.jiffy(before, valve_, dosing_.phase() != DosingCycle::Phase::idle || follow_up_.active());
  recorder_.record(raw_sample_, std::int32_t(std::lround(filtered_weight_g())), static_cast<std::uint8_t>(valve_));
  continue_print();
  continue_log_print();

  Outputs out;
  out.valve = valve_;
  out.valve_delay_100us = dosing_.phase() == DosingCycle::Phase::idle ? 0 : dosing_.valve_delay_100us();
  valve_delay_100us_ = out.valve_delay_100us;
  out.answered_counter = inputs.load_cell.counter;
  const ToleranceFollowUp::Phase follow_up = follow_up_.phase();
  out.state = fault_ != Fault::none ? IndicatorState::fault
              : dosing_.phase() == DosingCycle::Phase::dosing || test_.active ||
                      follow_up == ToleranceFollowUp::Phase::pulsing
                  ? IndicatorState::dosing
              : dosing_.phase() == DosingCycle::Phase::settling || follow_up_.active() ? IndicatorState::settling
                                                                                        : IndicatorState::idle;
  out.weight_100mg = weight_known() ? std::int32_t(std::lround(filtered_weight_g() * 10.0f)) : kWeightUnknown100mg;
  out.settings_changed = settings_changed_;
  out.busy = busy();
  report_telemetry(out);
  return out;
}

void Indicator::report_telemetry(Outputs& out) const {
  const Calibration& cal = settings_.calibration;
  out.filtered_g = filtered_weight_g();
  out.net_g = cal.valid() ? (screened_counts_ - zero_relative_counts()) / cal.counts_per_gram - tare_g_ : 0.0f;
  out.predicted_g = dosing_.last_prediction_g();
  out.fault = fault_;
}

void Indicator::receive_console(const Inputs& inputs) {
  for (std::size_t i = 0; i < inputs.console_rx_length; ++i) {
    const ConsoleLineReader::Event event = reader_.feed(inputs.console_rx[i]);
    echo_typed(reader_.echo());
    if (event == ConsoleLineReader::Event::none) continue;
    if (queue_count_ == kQueue) {
      error(3, "busy");  // more lines than a console can have in flight: refuse, do not lose silently
      continue;
    }
    QueuedLine& slot = queue_[(queue_head_ + queue_count_) % kQueue];
    slot.too_long = event == ConsoleLineReader::Event::too_long;
    std::strncpy(slot.text, slot.too_long ? "" : reader_.line(), sizeof slot.text);
    slot.text[sizeof slot.text - 1] = '\0';
    ++queue_count_;
  }
}

void Indicator::echo_typed(const char* text) {
  if (settings_.parameters.get(ParameterId::echo) != 0.0f) console_.write(text);
}

void Indicator::execute_queued_commands() {
  while (queue_count_ > 0 && !printing_ && !log_print_.active && answers_after_save_ == 0 && console_.free_space() >= kRoomForAnAnswer) {
    QueuedLine& line = queue_[queue_head_];
    if (line.too_long) {
      error(2, "line too long");
    } else {
      execute(line.text);
    }
    queue_head_ = (queue_head_ + 1) % kQueue;
    --queue_count_;
  }
}

void Indicator::process_sample(const LoadCellInput& sample) {
  if (sample.link == LinkStatus::bus_off) raise(Fault::bus_off);
  if (!sample.fresh) {
    // A whole stale window in which the board heard nothing at all is the bus, not the load cell.
    silent_jiffies_ = sample.link == LinkStatus::silent ? silent_jiffies_ + 1 : 0;
    if (++stale_jiffies_ >= kStaleLimitJiffies) {
      raise(silent_jiffies_ >= kStaleLimitJiffies ? Fault::can_silence : Fault::stale_sample);
    }
    return;
  }
  stale_jiffies_ = 0;
  silent_jiffies_ = 0;
  last_counter_ = sample.counter;
  if (sample.status & kLoadCellAdcError) raise(Fault::adc_error);
  if (sample.status & kLoadCellOverload) raise(Fault::overload);
  if (sample.status & kLoadCellUnderload) raise(Fault::underload);
  if (!has_reference_) {
    reference_counts_ = sample.raw_counts;
    has_reference_ = true;
  }
  raw_sample_ = sample.raw_counts;
  raw_counts_ = relative_counts(sample.raw_counts);
  Fault jump = Fault::none;
  screened_counts_ = supervisor_.screen_sample(
      raw_counts_, settings_.calibration.valid() ? settings_.calibration.counts_per_gram : 0.0f,
      dosing_.phase() != DosingCycle::Phase::idle, jump);
  if (jump != Fault::none) raise(jump);
  has_sample_ = true;
  filtered_counts_ = filter_.push(screened_counts_);
  if (settings_.calibration.valid() &&
      filtered_weight_g() + tare_g_ > settings_.parameters.get(ParameterId::capacity_g) + kOverloadMarginG) {
    raise(Fault::overload);
  }
}

// The fault supervisor's watch over valve, flow and sensor, before any command of this jiffy: a
// fault it finds closes the valve in this jiffy's outputs.
void Indicator::supervise(const Inputs& inputs) {
  // A link that carries nothing brings no news of the valve either: its last feedback would read as
  // a valve that never moved. The link's own fault speaks for this jiffy.
  if (inputs.load_cell.link != LinkStatus::ok) return;
  FaultSupervisor::Observation o;
  o.command_in_force = valve_;
  o.command_delay_ms = float(valve_delay_100us_) / 10.0f;
  o.position = inputs.valve_position;
  o.dose_flowing = dosing_.phase() == DosingCycle::Phase::dosing;
  o.dose_running = dosing_.phase() != DosingCycle::Phase::idle;
  o.fresh_sample = inputs.load_cell.fresh;
  o.raw_counts = relative_counts(inputs.load_cell.raw_counts);
  o.counts_per_gram = settings_.calibration.valid() ? settings_.calibration.counts_per_gram : 0.0f;
  o.filtered_g = filtered_weight_g();
  const Fault found = supervisor_.watch(o);
  if (found != Fault::none) raise(found);
  const ValveTimingMonitor& timing = supervisor_.valve_timing();
  const auto seen = timing.strokes(ValveTimingMonitor::closing) > 0 ? ValveTimingMonitor::closing
                                                                     : ValveTimingMonitor::opening;
  dosing_.measured_valve_travel(timing.mean_arrival_ms(seen) / 1000.0f, timing.strokes(seen));
  dosing_.valve_could_deliver(supervisor_.dose_valve_could_deliver());
}

void Indicator::advance_dose() {
  dosing_.watch_standstill(filtered_weight_g());
  if (dosing_.phase() == DosingCycle::Phase::idle) return;
  const Calibration& cal = settings_.calibration;
  const float net_g = (screened_counts_ - zero_relative_counts()) / cal.counts_per_gram - tare_g_;
  switch (dosing_.step(net_g, filtered_weight_g(), stale_jiffies_ == 0)) {
    case DosingCycle::Outcome::running:
      return;
    case DosingCycle::Outcome::timed_out:
      raise(Fault::dose_timeout);
      return;
    case DosingCycle::Outcome::never_stable:
      raise(Fault::never_stable);
      return;
    case DosingCycle::Outcome::nothing_delivered:
      raise(Fault::no_flow);
      return;
    case DosingCycle::Outcome::certified:
      break;
  }
  const DoseResult& r = dosing_.result();
  if (r.strategy == DosingStrategy::learn) {
    settings_.learning.learn(dosing_.learning_key(), float(r.final_g - r.target_g));
    settings_changed_ = true;
  }
  if (r.strategy == DosingStrategy::twostage) {
    settings_.parameters.set(ParameterId::twostage_preact_g, dosing_.two_stage().fine_preact_g());
    settings_.parameters.set(ParameterId::twostage_coarse_g, dosing_.two_stage().coarse_g());
    settings_changed_ = true;
  }
  if (r.strategy == DosingStrategy::pac) {
    settings_.baselines.pac = dosing_.pac().learned();
    settings_changed_ = true;
  }
  if (r.strategy == DosingStrategy::flowpreact) {
    settings_.baselines.flowpreact = dosing_.flow_preact().learned();
    settings_changed_ = true;
  }
  conclude_dose();
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
  while (printing_ && console_.free_space() >= kRoomForARecord) {
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
