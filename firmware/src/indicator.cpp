#include "dynweigh/firmware/indicator.hpp"

#include <cmath>

#include "console_commands.hpp"

namespace dynweigh::firmware {

Indicator::Indicator(const PersistentSettings& settings) : settings_(settings) {
  scale_.start(settings_.calibration);
  // The parameters in force are the selected material's, whoever set them.
  settings_.materials.follow_parameter(ParameterId::density, settings_.parameters);
  settings_.materials.follow_parameter(ParameterId::oiml_class, settings_.parameters);
  apply_parameters();
}

void Indicator::apply_parameters() {
  const Parameters& p = settings_.parameters;
  scale_.configure(p);
  dosing_.configure(p);
  follow_up_.configure(p);
  supervisor_.configure(p);
  discharge_.configure(p);
}

Outputs Indicator::step(const Inputs& inputs) {
  settings_changed_ = false;
  jiffy_ = inputs.jiffy;
  gate_position_ = inputs.gate_position;
  ingredient_valves_ = inputs.ingredient_valves;
  sense(inputs);
  supervise(inputs);
  command(inputs.load_cell.fresh);
  dose();
  actuate();
  return report(inputs);
}

// The jiffy's news: the board's word on the last save, the console's bytes, the load cell's sample
// (through the supervisor's outlier screen and the display filter).
void Indicator::sense(const Inputs& inputs) {
  answer_after_save(inputs.settings_save);
  console_.receive(inputs.console_rx, inputs.console_rx_length,
                   settings_.parameters.get(ParameterId::echo) != 0.0f);
  if (!inputs.load_cell.fresh) return;
  const Calibration& cal = settings_.calibration;
  const float counts = scale_.take(inputs.load_cell.raw_counts);
  // A sample that brings a fault of its own ends the dose in this jiffy's supervision: it is
  // screened as one outside a dose.
  const bool strict = dose_running() && FaultSupervisor::sample_fault(inputs.load_cell) == Fault::none;
  scale_.filter(supervisor_.screen_sample(counts, cal.valid() ? cal.counts_per_gram : 0.0f, strict));
}

// Every fault, before any command of this jiffy: one found closes the valve in this jiffy's outputs.
void Indicator::supervise(const Inputs& inputs) {
  const Calibration& cal = settings_.calibration;
  raise(supervisor_.watch_sample(inputs.load_cell, cal.valid(), scale_.filtered_gross_g(cal), dose_running()));
  if (inputs.gate_faults != 0) raise(Fault::gate_fault);  // the module knows its gate best
  // A link that carries nothing brings no news of the valve either: its last feedback would read as
  // a valve that never moved. The link's own fault speaks for this jiffy.
  if (inputs.load_cell.link != LinkStatus::ok) return;
  FaultSupervisor::Observation o;
  o.command_in_force = valve_;
  o.command_delay_ms = float(valve_delay_100us_) / 10.0f;
  o.position = inputs.valve_position;
  o.dose_flowing = dosing_.phase() == DosingCycle::Phase::dosing;
  o.dose_running = dose_running();
  o.fresh_sample = inputs.load_cell.fresh;
  o.raw_counts = scale_.relative_counts(inputs.load_cell.raw_counts);
  o.counts_per_gram = cal.valid() ? cal.counts_per_gram : 0.0f;
  o.filtered_g = filtered_weight_g();
  raise(supervisor_.watch(o));
  const ValveTimingMonitor& timing = supervisor_.valve_timing();
  const auto seen = timing.strokes(ValveTimingMonitor::closing) > 0 ? ValveTimingMonitor::closing
                                                                     : ValveTimingMonitor::opening;
  dosing_.measured_valve_travel(timing.mean_arrival_ms(seen) / 1000.0f, timing.strokes(seen));
  dosing_.measured_half_travel(timing.mean_motion_ms(ValveTimingMonitor::to_half) / 1000.0f);
  dosing_.valve_could_deliver(supervisor_.dose_valve_could_deliver());
}

// The console's queued lines, and a `zero` or `cal` waiting for standstill.
void Indicator::command(bool fresh_sample) {
  run_queued_lines();
  answer_adjustment(scale_.advance_adjustment(fresh_sample, settings_.calibration, settings_.parameters));
}

// The dosing cycle on this jiffy's sample, what follows its certified result, and the discharge.
void Indicator::dose() {
  advance_dose();
  advance_discharge();
}

// The valve command in force: closed on a fault, else the dose's, its top-up's, or the test
// cycle's or manual one. The gate opens only for a discharge, and closes on a fault.
void Indicator::actuate() {
  const ValveCommand scheduled = advance_test_cycle();
  const ValveCommand before = valve_;
  if (fault_ != Fault::none) {
    valve_ = ValveCommand::closed;
  } else if (dose_running()) {
    valve_ = dosing_.valve();
  } else if (follow_up_.active()) {
    valve_ = ValveCommand::closed;  // held for the operator
  } else {
    valve_ = scheduled;
  }
  valve_delay_100us_ = dose_running() ? dosing_.valve_delay_100us() : 0;
  selected_totals().jiffy(before, valve_, dose_running() || follow_up_.active());
  const GateCommand gate_before = gate_;
  gate_ = fault_ == Fault::none ? discharge_.gate() : GateCommand::closed;
  if (gate_before == GateCommand::closed && gate_ == GateCommand::open) ++selected_totals().gate_cycles;
}

// The test-data recorder, the listings being printed, and the jiffy's Outputs.
Outputs Indicator::report(const Inputs& inputs) {
  recorder_.record(scale_.raw_sample(), std::int32_t(std::lround(filtered_weight_g())),
                   static_cast<std::uint8_t>(valve_));
  continue_print();
  continue_log_print();
  Outputs out;
  out.valve = valve_;
  out.ingredient = ingredient_;
  out.gate = gate_;
  out.valve_delay_100us = valve_delay_100us_;
  out.answered_counter = inputs.load_cell.counter;
  out.state = state_of(activity());
  out.weight_100mg = weight_known() ? std::int32_t(std::lround(filtered_weight_g() * 10.0f)) : kWeightUnknown100mg;
  out.settings_changed = settings_changed_;
  out.busy = busy();
  report_telemetry(out);
  return out;
}

void Indicator::report_telemetry(Outputs& out) const {
  const Calibration& cal = settings_.calibration;
  out.filtered_g = filtered_weight_g();
  out.net_g = cal.valid() ? scale_.screened_net_g(cal) : 0.0f;
  out.predicted_g = dosing_.last_prediction_g();
  out.fault = fault_;
}

bool Indicator::weight_known() const {
  return scale_.has_sample() && !supervisor_.sample_stale() && settings_.calibration.valid();
}

Indicator::Activity Indicator::activity() const {
  const ToleranceFollowUp::Phase follow_up = follow_up_.phase();
  const DosingCycle::Phase phase = dosing_.phase();
  if (fault_ != Fault::none) return Activity::fault;
  if (follow_up == ToleranceFollowUp::Phase::holding) return Activity::hold;
  if (phase == DosingCycle::Phase::dosing || phase == DosingCycle::Phase::pulsing || test_.active) {
    return Activity::dosing;
  }
  if (phase == DosingCycle::Phase::settling) return Activity::settling;
  if (discharge_.active()) return Activity::discharging;
  return Activity::idle;
}

const char* Indicator::activity_name(Activity activity) {
  switch (activity) {
    case Activity::idle: return "idle";
    case Activity::dosing: return "dosing";
    case Activity::settling: return "settling";
    case Activity::hold: return "hold";
    case Activity::fault: return "fault";
    case Activity::discharging: return "discharging";
  }
  return "idle";
}

IndicatorState Indicator::state_of(Activity activity) {
  switch (activity) {
    case Activity::idle: return IndicatorState::idle;
    case Activity::dosing:
    case Activity::discharging: return IndicatorState::dosing;
    case Activity::settling:
    case Activity::hold: return IndicatorState::settling;
    case Activity::fault: return IndicatorState::fault;
  }
  return IndicatorState::idle;
}

// A dose's test-data recording runs on after its result and is no part of it: the next dose
// restarts it (`readtestdata info` tells which dose the recorder holds).
bool Indicator::cycle_running() const {
  return dose_running() || test_.active || scale_.adjusting() || follow_up_.active() || discharge_.active();
}

// A dose held for the operator waits on the console: a script may send `accept` or `topup`.
bool Indicator::busy() const {
  const bool holding = follow_up_.phase() == ToleranceFollowUp::Phase::holding;
  return console_.queued() > 0 || printing_ || log_print_.active || console_.answers_held() ||
         (cycle_running() && !holding);
}

// Settings that did not reach the storage hold only until power is lost: a fault, not an OK.
void Indicator::answer_after_save(SettingsSave report) {
  if (report == SettingsSave::failed) raise(Fault::nvm_error);
  console_.release_held_answers(report == SettingsSave::failed);
}

bool Indicator::reject_if_busy() {
  if (!cycle_running()) return false;
  console_.error(3, "busy");
  return true;
}

void Indicator::raise(Fault fault) {
  if (fault == Fault::none || fault_ != Fault::none) return;  // the first cause is the one to report
  fault_ = fault;
  save_lessons();
  test_.scheduled = false;
  if (dose_running()) dosing_.abort();
  follow_up_.finish();
  discharge_.abort();
  if (batch_.active()) end_batch(false);  // BATCH ok=0 before the ERR
  if (dose_command_pending_ || discharge_command_pending_ || scale_.adjusting()) {
    dose_command_pending_ = false;
    discharge_command_pending_ = false;
    scale_.cancel_adjustment();
    console_.write("ERR 4 fault ");
    console_.line(fault_name(fault));
  }
}

void Indicator::run_queued_lines() {
  while (!printing_ && !log_print_.active) {
    Console::Line* line = console_.next_line();
    if (!line) return;
    if (line->too_long) {
      console_.error(2, "line too long");
    } else {
      ConsoleCommands::run(*this, line->text);
    }
    console_.pop_line();
  }
}

void Indicator::advance_dose() {
  const Calibration& cal = settings_.calibration;
  const float net_g = scale_.screened_net_g(cal);
  dosing_.watch_standstill(filtered_weight_g(), net_g, cal.valid() ? cal.counts_per_gram : 0.0f);
  if (!dose_running()) return;
  switch (dosing_.step(net_g, filtered_weight_g(), supervisor_.sample_current())) {
    case DosingCycle::Outcome::running:
      return;
    case DosingCycle::Outcome::timed_out:
      return raise(Fault::dose_timeout);
    case DosingCycle::Outcome::never_stable:
      return raise(Fault::never_stable);
    case DosingCycle::Outcome::nothing_delivered:
      return raise(Fault::no_flow);
    case DosingCycle::Outcome::reading_frozen:
      return raise(Fault::sensor_frozen);
    case DosingCycle::Outcome::certified:
      break;
  }
  if (follow_up_.topping_up()) return conclude_top_up();
  learn_from_result();
  conclude_dose();
}

// What a certified dose taught its strategy is kept with the settings.
void Indicator::learn_from_result() {
  const DoseResult& r = dosing_.result();
  if (r.strategy == DosingStrategy::learn) {
    settings_.learning.learn(dosing_.learning_key(), float(r.final_g - r.target_g));
    lessons_unsaved_ = true;
  }
  if (r.strategy == DosingStrategy::model || r.strategy == DosingStrategy::learn) {
    settings_.materials.keep_learned(dosing_.model_learned());
    lessons_unsaved_ = true;
  }
  if (r.strategy == DosingStrategy::twostage) {
    settings_.parameters.set(ParameterId::twostage_preact_g, dosing_.two_stage().fine_preact_g());
    settings_.parameters.set(ParameterId::twostage_coarse_g, dosing_.two_stage().coarse_g());
    lessons_unsaved_ = true;
  }
  if (r.strategy == DosingStrategy::pac) {
    settings_.baselines.pac = dosing_.pac().learned();
    lessons_unsaved_ = true;
  }
  if (r.strategy == DosingStrategy::flowpreact) {
    settings_.baselines.flowpreact = dosing_.flow_preact().learned();
    lessons_unsaved_ = true;
  }
}

}  // namespace dynweigh::firmware
