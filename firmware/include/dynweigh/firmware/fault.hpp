#pragma once
#include <cstdint>

namespace dynweigh::firmware {

// A load cell samples every jiffy: this long without one, its reading is stale (a dose blind for
// this long ends in a fault, so the dosing cycle closes before it would be).
inline constexpr float kStaleSampleLimitMs = 100.0f;

// Why the indicator stopped. Latched until `clearfault`; the valve and the gate stay closed meanwhile.
enum class Fault : std::uint8_t {
  none = 0,
  overload,       // load cell reports overload, or the weight is above the scale's maximum
  underload,      // load cell reports underload
  adc_error,      // load cell reports a converter error
  stale_sample,   // no load-cell sample for kStaleSampleLimitMs
  dose_timeout,   // a dose did not reach its target within dose_timeout_s
  never_stable,   // after the close the weight never settled
  // The fault supervisor's (fault_supervisor.hpp):
  sample_jump,         // samples kept jumping further than the scale can move in a jiffy
  valve_stuck_open,    // commanded closed (or half), the feedback stays open
  valve_stuck_closed,  // commanded open or half, the feedback stays closed
  no_flow,             // a dose's valve open, the weight does not rise
  flow_after_close,    // the weight keeps rising long after the close
  sensor_frozen,       // the load cell repeats one value while the flow runs, or while grains land
  // The plant link's (io.hpp LinkStatus, reported by a CAN board):
  can_silence,  // nothing heard on the bus for 100 ms: the link, not just the load cell, is dead
  bus_off,      // the transport went bus-off (or its link down): no command reaches the valve
  // The board's settings storage (io.hpp SettingsSave):
  nvm_error,  // a save of calibration or parameters failed: they hold only until power is lost
  // The discharge cycle's (discharge_cycle.hpp):
  gate_not_open,    // commanded open, the gate's feedback did not say open within its stroke limit
  gate_not_closed,  // commanded closed, the gate's feedback did not say closed within its stroke limit
  not_empty,        // the gate open, the hopper did not empty within discharge_timeout_s
  gate_fault,       // the gate's module reports a fault of its own (a fault bit of its 0x1A8)
};

const char* fault_name(Fault fault);

}  // namespace dynweigh::firmware
