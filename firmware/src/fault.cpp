#include "dynweigh/firmware/fault.hpp"

namespace dynweigh::firmware {

const char* fault_name(Fault fault) {
  switch (fault) {
    case Fault::none: return "none";
    case Fault::overload: return "overload";
    case Fault::underload: return "underload";
    case Fault::adc_error: return "adc_error";
    case Fault::stale_sample: return "stale_sample";
    case Fault::dose_timeout: return "dose_timeout";
    case Fault::never_stable: return "never_stable";
    case Fault::sample_jump: return "sample_jump";
    case Fault::valve_stuck_open: return "valve_stuck_open";
    case Fault::valve_stuck_closed: return "valve_stuck_closed";
    case Fault::no_flow: return "no_flow";
    case Fault::flow_after_close: return "flow_after_close";
    case Fault::sensor_frozen: return "sensor_frozen";
    case Fault::can_silence: return "can_silence";
    case Fault::bus_off: return "bus_off";
    case Fault::nvm_error: return "nvm_error";
    case Fault::gate_not_open: return "gate_not_open";
    case Fault::gate_not_closed: return "gate_not_closed";
    case Fault::not_empty: return "not_empty";
    case Fault::gate_fault: return "gate_fault";
  }
  return "unknown";
}

}  // namespace dynweigh::firmware
