// The dose on the console: `dose`, the manual `valve`, `abort`, and what the last model dose
// measured (`estimates`). `accept` and `topup`, on a held result: fill_conclusion.cpp.
#include <cmath>

#include "console_commands.hpp"

namespace dynweigh::firmware {

void ConsoleCommands::dose(Indicator& indicator, const Arguments& args) {
  Console& console = indicator.console_;
  const Parameters& p = indicator.settings_.parameters;
  long target = 0;
  DosingStrategy strategy = DosingStrategy::model;
  if (args.count < 2 || args.count > 3) return console.error(2, "usage: dose <grams> [<strategy>]");
  if (!parse_int(args.word[1], 1, long(p.get(ParameterId::capacity_g)), target)) {
    return console.error(2, "target out of range");
  }
  if (args.count == 3 && !parse_strategy(args.word[2], strategy)) return console.error(2, "unknown strategy");
  if (!strategy_available(strategy)) return console.error(2, "strategy not in this build");
  if (indicator.reject_if_busy()) return;
  // A dose owns the valve and ends with it closed; started over a manually opened valve, the
  // manual command would open it again after the result (found by fuzz/console_fuzzer.cpp).
  if (indicator.manual_valve_ != ValveCommand::closed) return console.error(3, "valve open (valve 0 first)");
  if (indicator.fault_ != Fault::none) return console.error(4, "fault active");
  if (!indicator.settings_.calibration.valid()) return console.error(5, "not calibrated");
  if (indicator.scale_.filtered_gross_g(indicator.settings_.calibration) + float(target) > p.get(ParameterId::capacity_g)) {
    return console.error(2, "target exceeds the scale's capacity");
  }
  indicator.start_dose(indicator.settings_.materials.selected(), std::int32_t(target), strategy);
}

void Indicator::start_dose(std::size_t material, std::int32_t target_g, DosingStrategy strategy) {
  const Material& entry = settings_.materials.at(material);
  dosing_.restore_baselines(settings_.baselines);
  dosing_.restore_material(entry.learned, entry.pulses);
  supervisor_.expect_dead_time_ms(entry.valve_slowest_dead_ms);
  dose_valve_watched_ = true;
  dosing_.start(target_g, strategy, &settings_.learning);
  offer_sizing_reading(settings_.parameters.get(ParameterId::topup_max) >= 1.0f);
  dose_command_pending_ = true;
  recorder_.start();
  recording_source_ = RecordingSource{true, ++doses_started_, target_g, strategy};
}

void ConsoleCommands::valve(Indicator& indicator, const Arguments& args) {
  Console& console = indicator.console_;
  long position = 0;
  if (args.count != 2 || !parse_int(args.word[1], 0, 2, position)) return console.error(2, "usage: valve <0|1|2>");
  if (indicator.reject_if_busy()) return;
  if (indicator.fault_ != Fault::none && position != 0) return console.error(4, "fault active");
  indicator.manual_valve_ = static_cast<ValveCommand>(position);
  indicator.ok();
}

// The running command that abort cuts short answers ERR 3 aborted, before abort's own OK.
void ConsoleCommands::abort(Indicator& indicator, const Arguments& args) {
  Console& console = indicator.console_;
  if (args.count != 1) return console.error(2, "usage: abort");
  if (indicator.dose_running()) indicator.dosing_.abort();
  indicator.save_lessons();  // what the dose's close and pulses taught before the abort is kept
  if (indicator.batch_.active()) indicator.end_batch(false);  // BATCH ok=0 before the ERR
  indicator.follow_up_.finish();  // a held or topping-up result is dropped, unlogged
  indicator.discharge_.abort();   // the gate is commanded closed, unproven
  if (indicator.dose_command_pending_ || indicator.discharge_command_pending_ || indicator.scale_.adjusting()) {
    indicator.dose_command_pending_ = false;
    indicator.discharge_command_pending_ = false;
    indicator.scale_.cancel_adjustment();
    console.error(3, "aborted");
  }
  indicator.test_.active = false;
  indicator.test_.scheduled = false;
  indicator.manual_valve_ = ValveCommand::closed;
  indicator.ok();
}

namespace {
void write_estimate(Console& out, const char* key, bool known, float value, int decimals) {
  out.put(' ');
  out.write(key);
  out.put('=');
  if (known) {
    out.write_decimal(value, decimals);
  } else {
    out.write("none");
  }
}

// What the selected material's fills taught (kept with it across restarts).
void write_learned(Console& console, std::size_t material, const MaterialLearning& learned) {
  const TwoParameterRls::State& law = learned.open_time_law;
  const bool law_known = law.fills > 0;
  console.write("LEARNED material=");
  console.write_int(std::int64_t(material));
  write_estimate(console, "law_flow_kg_s", law_known, law.theta1 / 1000.0f, 3);
  write_estimate(console, "law_offset_g", law_known, law.theta2, 1);
  console.write(" law_fills=");
  console.write_int(law.fills);
  write_estimate(console, "let_through_ms", learned.residual_fills > 0, 1000.0f * learned.close_let_through_s, 1);
  console.write(" let_through_fills=");
  console.write_int(learned.residual_fills);
  write_estimate(console, "law_longest_ms", law_known && learned.law_longest_open_s > 0.0f,
                 1000.0f * learned.law_longest_open_s, 0);
  const MeasuredCloseSpread& spread = learned.measured_closes;
  write_estimate(console, "close_spread", spread.closes() > 0, std::sqrt(spread.mean_square()), 2);
  console.write(" measured_closes=");
  console.write_int(spread.closes());
  console.put('\n');
}

// What the selected material's doses measured of the valve (kept with it across restarts).
void write_valve_timing(Console& console, std::size_t material, const Material& kept) {
  const ValveTimingLearning& valve = kept.learned.valve;
  console.write("VALVE material=");
  console.write_int(std::int64_t(material));
  write_estimate(console, "dead_ms", valve.dead_doses > 0, 1000.0f * valve.dead_s, 1);
  console.write(" dead_doses=");
  console.write_int(valve.dead_doses);
  write_estimate(console, "travel_ms", valve.travel_strokes > 0, 1000.0f * valve.travel_s, 1);
  console.write(" travel_strokes=");
  console.write_int(valve.travel_strokes);
  write_estimate(console, "slowest_dead_ms", kept.valve_slowest_dead_ms > 0.0f, kept.valve_slowest_dead_ms, 1);
  console.put('\n');
}

// What the selected material's top-up pulses taught, full and half open (kept with it across
// restarts): the law m = q e - c's flow q and loss c, how many pulses taught it, and the valve's
// travel to that opening as the pulses showed it.
void write_pulse_laws(Console& console, std::size_t material, const TopUpPulseLearning& pulses) {
  console.write("PULSES material=");
  console.write_int(std::int64_t(material));
  const struct {
    const char* flow;
    const char* loss;
    const char* count;
    const PulseLawLearning& law;
  } laws[] = {{"full_flow_g_s", "full_loss_g", " full_pulses=", pulses.full},
              {"half_flow_g_s", "half_loss_g", " half_pulses=", pulses.half}};
  for (const auto& l : laws) {
    write_estimate(console, l.flow, l.law.pulses > 0, l.law.law.theta1, 1);
    write_estimate(console, l.loss, l.law.pulses > 0, l.law.law.theta2, 1);
    console.write(l.count);
    console.write_int(l.law.pulses);
  }
  write_estimate(console, "full_travel_ms", pulses.full.pulses > 0, 1000.0f * pulses.full.travel_s, 1);
  write_estimate(console, "half_travel_ms", pulses.half.pulses > 0, 1000.0f * pulses.half.travel_s, 1);
  console.put('\n');
}
}  // namespace

void ConsoleCommands::estimates(Indicator& indicator, const Arguments& args) {
  Console& console = indicator.console_;
  if (args.count != 1) return console.error(2, "usage: estimates");
  const DoseEstimates<float>& e = indicator.dosing_.model_estimates();
  const MaterialTable& materials = indicator.settings_.materials;
  const MaterialLearning& learned = materials.at(materials.selected()).learned;
  const bool measured = e.impact_timed || e.measured;
  const DoseResult& last = indicator.dosing_.result();
  const bool model_dosed = last.target_g > 0 && (last.strategy == DosingStrategy::model || last.strategy == DosingStrategy::learn);
  // A close before the first impact measured nothing, but its plan tells why it closed where it did.
  // A dose of any strategy shows the valve's dead time: the material has learned that much.
  const bool kept = !learned.empty() || materials.at(materials.selected()).valve_slowest_dead_ms > 0.0f;
  if (!measured && !model_dosed && !kept) return console.error(2, "no model dose measured yet");
  if (measured || model_dosed) {
    const auto& s = e.signature;
    console.write("ESTIMATES");
    write_estimate(console, "impact_ms", e.impact_timed, 1000.0f * e.first_impact_s, 1);
    write_estimate(console, "dead_ms", e.impact_timed, 1000.0f * e.dead_time_s, 1);
    write_estimate(console, "dead_used_ms", true, 1000.0f * indicator.dosing_.model_dead_time_s(), 1);
    write_estimate(console, "stroke_used_ms", true, 1000.0f * indicator.dosing_.model_stroke_s(), 1);
    write_estimate(console, "flow_kg_s", e.measured, e.flow_kg_s, 3);
    write_estimate(console, "impulse_g", s.valid, 1000.0f * s.impulse_kg, 1);
    write_estimate(console, "impact_m_s", s.valid, s.impact_speed_m_s, 2);
    write_estimate(console, "outflow_m_s", s.valid, s.outflow_speed_m_s, 2);
    write_estimate(console, "fall_mm", s.valid, 1000.0f * s.implied_fall_height_m, 0);
    console.put('\n');
  }
  write_learned(console, materials.selected(), learned);
  write_valve_timing(console, materials.selected(), materials.at(materials.selected()));
  write_pulse_laws(console, materials.selected(), materials.at(materials.selected()).pulses);
  if (model_dosed) {
    const PlanChoice plan = indicator.dosing_.plan();
    console.write("PLAN plan=");
    console.write(dose_plan_name(plan.plan));
    write_estimate(console, "sigma_g", true, plan.sigma_g, 1);
    write_estimate(console, "limit_g", true, plan.limit_g, 1);
    write_estimate(console, "margin_g", true, plan.margin_g, 1);
    write_estimate(console, "fluctuation_pct", true, 100.0f * indicator.dosing_.flow_fluctuation(), 1);
    console.put('\n');
  }
  indicator.ok();
}

}  // namespace dynweigh::firmware
