#pragma once
// The loop every target runs: read the ports, step the indicator, apply its outputs.
#include <cstddef>

#include "dynweigh/firmware/indicator.hpp"
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
};

inline firmware::Outputs run_one_jiffy(firmware::Indicator& indicator, Ports& ports, std::uint32_t jiffy) {
  char rx[128];
  firmware::Inputs inputs;
  inputs.jiffy = jiffy;
  inputs.load_cell = ports.load_cell.read_sample();
  inputs.valve_position = ports.valve.position();
  inputs.console_rx = rx;
  inputs.console_rx_length = ports.console.read(rx, sizeof rx);
  inputs.settings_save = ports.save_report;
  if (ports.probe) ports.probe->before_step();
  const firmware::Outputs outputs = indicator.step(inputs);
  if (ports.probe) ports.probe->after_step(outputs);
  ports.valve.command(outputs.valve, outputs.valve_delay_100us);
  char tx[512];
  for (std::size_t room, n; (room = ports.console.writable()) > 0 &&
                            (n = indicator.drain_console(tx, room < sizeof tx ? room : sizeof tx)) > 0;) {
    ports.console.write(tx, n);
  }
  ports.save_report = !outputs.settings_changed || !ports.settings      ? firmware::SettingsSave::none
                      : ports.settings->save(indicator.settings()) ? firmware::SettingsSave::saved
                                                                   : firmware::SettingsSave::failed;
  return outputs;
}

}  // namespace dynweigh::hal
