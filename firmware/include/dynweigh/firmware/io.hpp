#pragma once
// What the indicator sees and does in one jiffy. Everything a board feeds it and takes from it
// passes through these two structs, so a recording of Inputs replays the firmware exactly; and
// everything a tool shows of it (the CSV, plots, replay, the PLC's registers) is read from Outputs.
#include <climits>
#include <cstddef>
#include <cstdint>

#include "dynweigh/schema/can_values.hpp"
#include "dynweigh/firmware/fault.hpp"

namespace dynweigh::firmware {

// The plant link's values (valve command and position, status bits, state) are the schema's.
using schema::GateCommand;
using schema::GatePosition;
using schema::IndicatorState;
using schema::kLoadCellAdcError;
using schema::kLoadCellOverload;
using schema::kLoadCellUnderload;
using schema::ValveCommand;
using schema::ValvePosition;

// The link that carries the samples, as the board sees it this jiffy. A board without a bus (an ADC
// on the board, the in-process plant) always says `ok`.
enum class LinkStatus : std::uint8_t {
  ok = 0,
  silent,   // nothing at all heard from the plant's nodes since the last jiffy
  bus_off,  // the transport can no longer send or receive (CAN bus-off, link down)
};

struct LoadCellInput {
  std::int32_t raw_counts = 0;
  std::uint16_t counter = 0;
  std::uint8_t status = 0;  // schema::kLoadCell* bits
  bool fresh = true;        // false: no sample arrived this jiffy
  LinkStatus link = LinkStatus::ok;
};

// The board's word on the settings the indicator asked it to keep in the last jiffy
// (Outputs::settings_changed): saved, failed, or `none` (nothing asked, or a board without storage).
enum class SettingsSave : std::uint8_t { none = 0, saved, failed };

struct Inputs {
  std::uint32_t jiffy = 0;
  LoadCellInput load_cell;
  ValvePosition valve_position = ValvePosition::closed;
  GatePosition gate_position = GatePosition::closed;  // a board without a gate reports it closed
  std::uint8_t gate_faults = 0;  // the gate module's fault bits (0x1A8 byte 1); any set is the fault gate_fault
  // Bit i: the plant has ingredient valve i (bit 0, the valve above, always). valve_position is the
  // feedback of the valve the last Outputs commanded (Outputs::ingredient).
  std::uint8_t ingredient_valves = 0x01;
  const char* console_rx = nullptr;  // bytes that arrived since the last jiffy
  std::size_t console_rx_length = 0;
  SettingsSave settings_save = SettingsSave::none;
};

// The 0x181 frame's weight before the first sample, while samples are stale and while the scale
// is not calibrated: no weight rather than one computed from nothing.
inline constexpr std::int32_t kWeightUnknown100mg = INT32_MIN;

struct Outputs {
  ValveCommand valve = ValveCommand::closed;
  GateCommand gate = GateCommand::closed;  // the discharge gate (0x228); a board without one ignores it
  // Whose valve `valve` commands: 0 the valve above (0x220), 1..7 a batch's ingredient valves
  // (0x221..0x227). Every other valve is commanded closed.
  std::uint8_t ingredient = 0;
  std::uint8_t valve_delay_100us = 0;  // 0x220 (docs/can-protocol.md): apply the command this much into the jiffy
  std::uint16_t answered_counter = 0;  // the sample this jiffy answers
  IndicatorState state = IndicatorState::idle;
  std::int32_t weight_100mg = 0;       // the 0x181 status frame's weight, or kWeightUnknown100mg
  bool settings_changed = false;       // the board should persist settings() now
  bool busy = false;                   // a command is still running (dose, test cycle, print)

  // Telemetry: what the indicator knows this jiffy, for tools; no board acts on it.
  float filtered_g = 0.0f;   // the display filter's net weight (0 while not calibrated)
  float net_g = 0.0f;        // this jiffy's sample, net of zero and tare, unfiltered (0 while not calibrated)
  float predicted_g = 0.0f;  // the strategy's last prediction of where the fill ends (0 before any)
  Fault fault = Fault::none;  // the latched fault, if state is fault
};

}  // namespace dynweigh::firmware
