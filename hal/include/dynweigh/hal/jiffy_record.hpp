#pragma once
// One jiffy as the board ran it, taken at the one seam every board shares (run_one_jiffy): the
// Inputs the indicator saw, console bytes included, and the Outputs it decided. Recording, replay,
// the CSV and the plots read these records, never the indicator's insides.
//
// The record is small and fixed-size, made on the stack each jiffy. The console bytes the
// indicator sent are counted here but not kept: a jiffy can send up to its console ring (4 KB),
// more than a small target's whole stack, so they go to a JiffyRecorder as they are sent.
#include <cstddef>
#include <cstdint>

#include "dynweigh/firmware/io.hpp"

namespace dynweigh::hal {

struct JiffyRecord {
  // The most console input a board hands the indicator in one jiffy.
  static constexpr std::size_t kConsoleRxBytes = 128;

  std::uint32_t jiffy = 0;
  firmware::LoadCellInput load_cell;
  firmware::ValvePosition valve_position = firmware::ValvePosition::closed;
  firmware::GatePosition gate_position = firmware::GatePosition::closed;
  std::uint8_t ingredient_valves = 0x01;
  std::uint8_t gate_faults = 0;
  firmware::SettingsSave settings_save = firmware::SettingsSave::none;
  char console_rx[kConsoleRxBytes] = {};
  std::size_t console_rx_length = 0;

  firmware::Outputs outputs;
  std::size_t console_tx_length = 0;  // bytes sent to the console this jiffy

  // The Inputs the indicator saw; they point into this record, so they live as long as it does.
  firmware::Inputs inputs() const {
    firmware::Inputs in;
    in.jiffy = jiffy;
    in.load_cell = load_cell;
    in.valve_position = valve_position;
    in.gate_position = gate_position;
    in.ingredient_valves = ingredient_valves;
    in.gate_faults = gate_faults;
    in.console_rx = console_rx;
    in.console_rx_length = console_rx_length;
    in.settings_save = settings_save;
    return in;
  }
};

// Where a board sends its jiffies to be kept (a recording file on a host). It gets the console
// bytes as they go out, then the finished record. It must not wait: a jiffy is 10 ms.
class JiffyRecorder {
 public:
  virtual ~JiffyRecorder() = default;
  virtual void console_sent(const char* data, std::size_t length) = 0;
  virtual void record(const JiffyRecord& jiffy) = 0;
};

}  // namespace dynweigh::hal
