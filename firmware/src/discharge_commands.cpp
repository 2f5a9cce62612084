// The discharge on the console: `discharge` empties the weigh hopper through its gate (and, with
// auto_discharge 1, every certified dose does before its OK; fill_conclusion.cpp).
#include "console_commands.hpp"

namespace dynweigh::firmware {

void ConsoleCommands::discharge(Indicator& indicator, const Arguments& args) {
  Console& console = indicator.console_;
  if (args.count != 1) return console.error(2, "usage: discharge");
  if (indicator.reject_if_busy()) return;
  if (indicator.manual_valve_ != ValveCommand::closed) return console.error(3, "valve open (valve 0 first)");
  if (indicator.fault_ != Fault::none) return console.error(4, "fault active");
  if (!indicator.settings_.calibration.valid()) return console.error(5, "not calibrated");
  indicator.start_discharge();
}

void Indicator::start_discharge() {
  discharge_.start();
  discharge_command_pending_ = true;
}

// A fault the cycle finds is raised like any other: every valve and the gate close in this jiffy's
// outputs, and the pending command answers ERR 4 fault <name>.
void Indicator::advance_discharge() {
  if (!discharge_.active()) return;
  switch (discharge_.step(scale_.filtered_gross_g(settings_.calibration), gate_position_)) {
    case DischargeCycle::Outcome::running:
      return;
    case DischargeCycle::Outcome::gate_not_open:
      return raise(Fault::gate_not_open);
    case DischargeCycle::Outcome::gate_not_closed:
      return raise(Fault::gate_not_closed);
    case DischargeCycle::Outcome::not_empty:
      return raise(Fault::not_empty);
    case DischargeCycle::Outcome::emptied:
      break;
  }
  if (!discharge_command_pending_) return;
  discharge_command_pending_ = false;
  ok();
}

}  // namespace dynweigh::firmware
