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
  }
  return "unknown";
}

}  // namespace dynweigh::firmware
