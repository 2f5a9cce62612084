// The scale on the console: `tare`, `zero`, `cal`, and `clearfault` (the sample's faults are the
// scale's first); and the answers of `zero` and `cal` once the reading stands still (scale.hpp).
#include "console_commands.hpp"

namespace dynweigh::firmware {

void ConsoleCommands::tare(Indicator& indicator, const Arguments& args) {
  Console& console = indicator.console_;
  if (args.count != 1) return console.error(2, "usage: tare");
  if (indicator.reject_if_busy()) return;
  if (!indicator.settings_.calibration.valid()) return console.error(5, "not calibrated");
  indicator.scale_.tare(indicator.settings_.calibration);
  indicator.ok();
}

// `zero` and `cal` answer once the reading stands still (answer_adjustment below).
void ConsoleCommands::zero(Indicator& indicator, const Arguments& args) {
  if (args.count != 1) return indicator.console_.error(2, "usage: zero");
  if (indicator.reject_if_busy()) return;
  indicator.scale_.start_adjustment(Scale::Adjustment::zero, 0);
}

void ConsoleCommands::cal(Indicator& indicator, const Arguments& args) {
  Console& console = indicator.console_;
  long grams = 0;
  if (args.count != 2) return console.error(2, "usage: cal <grams>");
  if (!parse_int(args.word[1], 1, long(indicator.settings_.parameters.get(ParameterId::capacity_g)), grams)) {
    return console.error(2, "load out of range");
  }
  if (indicator.reject_if_busy()) return;
  if (!indicator.settings_.calibration.zero_set) return console.error(5, "zero the empty scale first");
  indicator.scale_.start_adjustment(Scale::Adjustment::span, std::int32_t(grams));
}

void ConsoleCommands::clearfault(Indicator& indicator, const Arguments& args) {
  Console& console = indicator.console_;
  if (args.count != 1) return console.error(2, "usage: clearfault");
  indicator.fault_ = Fault::none;
  indicator.supervisor_.clear();  // a cause still present is found again from scratch
  indicator.scale_.restart_filter();
  indicator.manual_valve_ = ValveCommand::closed;
  indicator.ok();
}

void Indicator::answer_adjustment(Scale::AdjustmentEnd end) {
  switch (end) {
    case Scale::AdjustmentEnd::running:
      return;
    case Scale::AdjustmentEnd::in_motion:
      return console_.error(3, "in motion");
    case Scale::AdjustmentEnd::span_too_small:
      return console_.error(2, "load too small to calibrate");
    case Scale::AdjustmentEnd::zero_set:
    case Scale::AdjustmentEnd::zero_adjusted:
      settings_changed_ = true;
      supervisor_.reset();  // its outlier screen held counts relative to the old reference
      if (end == Scale::AdjustmentEnd::zero_adjusted) {
        console_.line("NOTE adjustment: new zero; no span until cal <grams> with a test weight");
      }
      return ok();
    case Scale::AdjustmentEnd::span_set:
    case Scale::AdjustmentEnd::span_coarse:
      settings_changed_ = true;
      if (end == Scale::AdjustmentEnd::span_coarse) {
        console_.write("NOTE coarse span: ");
        console_.write_decimal(1.0f / settings_.calibration.counts_per_gram, 1);
        console_.line(" g per count; a heavier test weight or more gain resolves the scale better");
      }
      return ok();
  }
}

}  // namespace dynweigh::firmware
