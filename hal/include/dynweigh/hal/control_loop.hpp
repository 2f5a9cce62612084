#pragma once
// The loop every target runs: read the ports, step the indicator, apply its outputs. Each jiffy
// comes back as a JiffyRecord (jiffy_record.hpp), the one place a board or a tool learns what happened.
#include <cstddef>

#include "dynweigh/firmware/indicator.hpp"
#include "dynweigh/hal/jiffy_record.hpp"
#include "dynweigh/hal/ports.hpp"

namespace dynweigh::hal {

struct Ports {
  LoadCellPort& load_cell;
  ValvePort& valve;
  ConsolePort& console;
  SettingsStore* settings = nullptr;  // nothing persists without one
  // How the save asked for in the last jiffy went: the next jiffy's Inputs tell the indicator, so
  // a recording of Inputs replays a failed save too. A board keeps it from one jiffy to the next.
  firmware::SettingsSave save_report = firmware::SettingsSave::none;
  StepProbe* probe = nullptr;
  JiffyRecorder* recorder = nullptr;  // every jiffy's record goes here too, if set (dynweigh-fw --record)
  GatePort* gate = nullptr;  // the discharge gate; without one it reads closed and commands go nowhere
  IngredientValvesPort* ingredients = nullptr;  // ingredient valves 1..7; without them only ingredient 0
};

// The feedback of the valve the indicator commanded last (a batch's ingredient, else ingredient 0's).
inline firmware::ValvePosition commanded_valve_position(const firmware::Indicator& indicator, const Ports& ports) {
  const std::uint8_t ingredient = indicator.valve_ingredient();
  if (ingredient == 0 || !ports.ingredients) return ports.valve.position();
  return ports.ingredients->position(ingredient);
}

// The valve command goes to the ingredient it names; every other valve is commanded closed.
inline void command_valves(const firmware::Outputs& outputs, Ports& ports) {
  if (outputs.ingredient == 0 || !ports.ingredients) {
    ports.valve.command(outputs.ingredient == 0 ? outputs.valve : firmware::ValveCommand::closed,
                        outputs.ingredient == 0 ? outputs.valve_delay_100us : 0);
  } else {
    ports.valve.command(firmware::ValveCommand::closed, 0);
  }
  if (ports.ingredients) ports.ingredients->command(outputs.ingredient, outputs.valve, outputs.valve_delay_100us);
}

// One jiffy: read the ports, step the indicator, apply its outputs, and say what happened.
inline JiffyRecord run_one_jiffy(firmware::Indicator& indicator, Ports& ports, std::uint32_t jiffy) {
  JiffyRecord record;
  record.jiffy = jiffy;
  record.load_cell = ports.load_cell.read_sample();
  record.valve_position = commanded_valve_position(indicator, ports);
  record.ingredient_valves = ports.ingredients ? std::uint8_t(ports.ingredients->present() | 1u) : std::uint8_t(1);
  record.gate_position = ports.gate ? ports.gate->position() : firmware::GatePosition::closed;
  record.gate_faults = ports.gate ? ports.gate->faults() : std::uint8_t(0);
  record.console_rx_length = ports.console.read(record.console_rx, sizeof record.console_rx);
  record.settings_save = ports.save_report;
  if (ports.probe) ports.probe->before_step();
  record.outputs = indicator.step(record.inputs());
  if (ports.probe) ports.probe->after_step(record.outputs);
  const firmware::Outputs& outputs = record.outputs;
  command_valves(outputs, ports);
  if (ports.gate) ports.gate->command(outputs.gate);
  char tx[512];
  for (std::size_t room, n; (room = ports.console.writable()) > 0 &&
                            (n = indicator.drain_console(tx, room < sizeof tx ? room : sizeof tx)) > 0;) {
    ports.console.write(tx, n);
    record.console_tx_length += n;
    if (ports.recorder) ports.recorder->console_sent(tx, n);
  }
  ports.save_report = !outputs.settings_changed || !ports.settings      ? firmware::SettingsSave::none
                      : ports.settings->save(indicator.settings()) ? firmware::SettingsSave::saved
                                                                   : firmware::SettingsSave::failed;
  if (ports.recorder) ports.recorder->record(record);
  return record;
}

}  // namespace dynweigh::hal
