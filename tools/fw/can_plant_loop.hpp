#pragma once
// dynweigh-fw --plant can:<transport>: the indicator on the Linux CAN board (hal/linux) against an
// external plant (dynweigh plant, real modules, HIL replay).
#include <cstdint>
#include <string>

namespace dynweigh::tools {

class PlcLink;

struct CanPlantOptions {
  std::string transport;  // after "can:"
  std::string console = "stdio";
  bool realtime = false;
  std::string csv;
  std::string nvm;
  bool nvm_reset = false;
  std::string pty_link;
  double plant_timeout_s = 10.0;  // lockstep: no first sample within this long is an error (0: wait)
  PlcLink* plc = nullptr;         // --modbus, or nothing
  std::string record;             // --record FILE: every jiffy for dynweigh replay, or nothing
};

// Exit status when a lockstep plant never sent a sample within plant_timeout_s.
inline constexpr int kExitNoPlant = 3;

// Returns the process exit status; throws std::runtime_error with a one-line reason at set-up.
int run_can_plant(const CanPlantOptions& options);

}  // namespace dynweigh::tools
