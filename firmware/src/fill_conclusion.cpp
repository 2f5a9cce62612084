// What becomes of a certified result: judged against its tolerance bands, then reported (a RESULT
// line and a logbook record), topped up, or held for the operator's `accept` or `topup`.
#include <cmath>

#include "console_commands.hpp"

namespace dynweigh::firmware {

void Indicator::conclude_dose() {
  concluding_ = dosing_.result();
  follow_up_.begin();
  judge_result();
}

// A top-up pulse certified: what it delivered sizes the next one; a pulse the scale saw nothing of
// ends the top-up with the result as it is, or in `no_flow` where the whole dose brought nothing.
// A reading that only sizes a pulse must be followed by one: where the pulse may have moved nothing
// (what it brought within the reading's standard error of nothing) or the reading is found frozen,
// the reading is certified in full before the pulse is judged.
void Indicator::conclude_top_up() {
  const float delivered_g = float(dosing_.result().final_g - concluding_.final_g);
  const bool reading_may_size =
      !dosing_.reading_frozen() && !dosing_.pulse_moved_nothing(delivered_g - SizingReading::kStandardErrorG);
  if (dosing_.reading_sizes_only() && !reading_may_size) return dosing_.certify_in_full();
  if (!dosing_.learn_top_up(delivered_g)) {
    if (supervisor_.last_opening_reached_open() && dosing_.dose_delivered_nothing()) return raise(Fault::no_flow);
    follow_up_.stop_topping_up();
  }
  keep_top_up_learning();
  concluding_ = dosing_.result();
  follow_up_.finish();
  judge_result();
}

// What a sized pulse taught stays with the material, for the next dose's pulses (a baseline's fixed
// pulses teach nothing), saved with the dose's other lessons when it ends.
void Indicator::keep_top_up_learning() {
  if (!dosing_.sizes_top_ups()) return;
  const TopUpPulseLearning pulses = dosing_.top_up_learning();
  if (pulses.empty()) return;
  settings_.materials.keep_pulses(pulses);
  lessons_unsaved_ = true;
}

// What the valve's feedback showed of its dead time while the dose ran (its close and its pulses,
// whatever the strategy) stays with the material, once, when the dose ends.
void Indicator::keep_valve_dead_time() {
  if (!dose_valve_watched_) return;
  dose_valve_watched_ = false;
  const float dead_ms = supervisor_.dead_time_to_keep_ms();
  if (dead_ms == settings_.materials.at(settings_.materials.selected()).valve_slowest_dead_ms) return;
  settings_.materials.keep_valve_slowest_dead_ms(dead_ms);
  lessons_unsaved_ = true;
}

// One save per dose: a record written after every pulse would wear an EEPROM up to four times as
// fast. A power loss before it costs the dose's lessons, never the record before them.
void Indicator::save_lessons() {
  keep_valve_dead_time();
  if (!lessons_unsaved_) return;
  lessons_unsaved_ = false;
  settings_changed_ = true;
}

// How far short the model strategy leaves a fill without topping it up: its plan may have aimed
// short on purpose, and fills that all end just inside the warning band would average short by
// most of it. Its pulses weigh the chance of ending further short (top_up_pulse_law.hpp).
float Indicator::model_accepted_short_g() const {
  const ToleranceBands bands = tolerance_bands(float(concluding_.target_g), settings_.parameters);
  return model_top_up_shortfall_g(dosing_.plan().plan, bands.warn_low_g);
}

void Indicator::start_top_up() {
  follow_up_.start_top_up();
  const float accepted_short_g = concluding_.strategy == DosingStrategy::model ? model_accepted_short_g() : 0.0f;
  dosing_.start_top_up(float(concluding_.target_g - concluding_.final_g), follow_up_.pulse_s(),
                       follow_up_.pulses_left(), accepted_short_g);
  offer_sizing_reading(follow_up_.pulses_left() > 0);
}

// Where another pulse may follow the coming close or pulse, its reading need only size that pulse
// (sizing_reading.hpp); the bands below the target tell how short the fill may end without one.
void Indicator::offer_sizing_reading(bool pulse_may_follow) {
  const Parameters& p = settings_.parameters;
  const ToleranceBands bands = tolerance_bands(float(dosing_.result().target_g), p);
  const bool tol_topup = static_cast<ToleranceAction>(static_cast<int>(p.get(ParameterId::tol_action))) ==
                         ToleranceAction::topup;
  if (!pulse_may_follow) return dosing_.allow_sizing_reading(0.0f, 0.0f);
  dosing_.allow_sizing_reading(bands.warn_low_g, tol_topup ? bands.reject_low_g : 0.0f);
}

void Indicator::judge_result() {
  const Parameters& p = settings_.parameters;
  const float error_g = float(concluding_.final_g - concluding_.target_g);
  const ToleranceBands bands = tolerance_bands(float(concluding_.target_g), p);
  verdict_ = judge_tolerance(error_g, bands);
  // The model strategy finishes a fill short of its class itself, and not merely into the warning
  // band (model_accepted_short_g). tol_action judges what the top-ups left.
  const bool short_of_class = error_g < -model_accepted_short_g();
  const bool may_top_up = follow_up_.may_top_up() && !dosing_.reading_frozen();
  if (concluding_.strategy == DosingStrategy::model && short_of_class && may_top_up) {
    return start_top_up();
  }
  const auto action = static_cast<ToleranceAction>(static_cast<int>(p.get(ParameterId::tol_action)));
  if (action == ToleranceAction::topup && verdict_ == ToleranceVerdict::low && may_top_up) {
    return start_top_up();
  }
  // No pulse follows a reading that was to size one: it is certified in full, then judged again.
  if (dosing_.reading_sizes_only()) return dosing_.certify_in_full();
  if (!outside_reject_band(verdict_) || action == ToleranceAction::accept) return report_result();
  if (action == ToleranceAction::hold) return report_hold();
  report_result();  // topup: over the target, topup_max reached, or a pulse that moved nothing
}

// `<tag> target= final= error=`: how RESULT and HOLD lines begin.
void Indicator::write_fill_line_start(const char* tag) {
  console_.write(tag);
  console_.write(" target=");
  console_.write_int(concluding_.target_g);
  console_.write(" final=");
  console_.write_int(concluding_.final_g);
  console_.write(" error=");
  console_.write_int(concluding_.final_g - concluding_.target_g);
}

void Indicator::write_verdict_fields() {
  console_.write(" tolerance=");
  console_.write(tolerance_verdict_name(verdict_));
  console_.write(" topups=");
  console_.write_int(follow_up_.topups());
}

void Indicator::report_hold() {
  save_lessons();
  follow_up_.hold();
  dose_command_pending_ = false;
  write_fill_line_start("HOLD");
  write_verdict_fields();
  console_.put('\n');
  ok();
}

void Indicator::report_result() {
  save_lessons();
  follow_up_.finish();
  dose_command_pending_ = false;
  LogRecord record;
  record.jiffy = jiffy_;
  record.target_dg = concluding_.target_g * 10;
  record.final_dg = concluding_.final_g * 10;
  record.material = std::uint8_t(settings_.materials.selected());
  record.tolerance = verdict_;
  record.topups = follow_up_.topups();
  const bool logged = !logbook_ || logbook_->append(record);
  if (logged) last_sequence_ = logbook_ ? record.sequence : last_sequence_ + 1;
  Totalizers& totals = selected_totals();
  totals.total_g += std::uint64_t(concluding_.final_g > 0 ? concluding_.final_g : 0);
  ++totals.fills;
  const bool totals_kept = save_totals();
  write_fill_line_start("RESULT");
  console_.write(" time=");
  console_.write_int(concluding_.time_ms);
  console_.write(" cutoff=");
  console_.write_int(concluding_.cutoff_jiffy);
  console_.write(" strategy=");
  console_.write(strategy_name(concluding_.strategy));
  write_verdict_fields();
  console_.write(" material=");
  console_.write_int(std::int64_t(settings_.materials.selected()));
  console_.write(" plan=");
  console_.write(dose_plan_name(dosing_.plan().plan));
  console_.write(" seq=");
  console_.write_int(logged ? last_sequence_ : 0);
  console_.put('\n');
  if (!logged) {
    // A result the alibi memory could not keep is no certified fill: a fault, not an OK.
    raise(Fault::nvm_error);
    return console_.error(4, "fault nvm_error");
  }
  if (!totals_kept) raise(Fault::nvm_error);  // the fill is logged; its totals could not be kept
  // A batch's ingredient: the next one doses on top of it, the last one ends the batch.
  if (batch_.active() && fault_ == Fault::none && batch_.next(concluding_.final_g)) return start_batch_ingredient();
  if (batch_.active()) end_batch(fault_ == Fault::none);
  // The dose answers once the hopper is empty again: the next command finds it so.
  if (fault_ == Fault::none && settings_.parameters.get(ParameterId::auto_discharge) != 0.0f) return start_discharge();
  ok();
}

void ConsoleCommands::accept(Indicator& indicator, const Arguments& args) {
  Console& console = indicator.console_;
  if (args.count != 1) return console.error(2, "usage: accept");
  if (indicator.follow_up_.phase() != ToleranceFollowUp::Phase::holding) return console.error(2, "no result held");
  indicator.report_result();
}

void ConsoleCommands::topup(Indicator& indicator, const Arguments& args) {
  Console& console = indicator.console_;
  if (args.count != 1) return console.error(2, "usage: topup");
  if (indicator.follow_up_.phase() != ToleranceFollowUp::Phase::holding) return console.error(2, "no result held");
  if (indicator.fault_ != Fault::none) return console.error(4, "fault active");
  if (indicator.concluding_.final_g >= indicator.concluding_.target_g) return console.error(2, "not under the target");
  if (!indicator.follow_up_.may_top_up()) return console.error(2, "topup_max reached");
  if (indicator.dosing_.reading_frozen()) return console.error(2, "reading frozen");
  indicator.start_top_up();
  indicator.dose_command_pending_ = true;  // answers like the dose: RESULT, or HOLD again
}

}  // namespace dynweigh::firmware
