#pragma once
// dynweigh-fw --plant can:<transport>: the indicator on the Linux CAN board (hal/linux) against an
// external plant (dynweigh plant, real modules, HIL replay).
#include <cstdint>
#include <string>

namespace dynweigh::tools {

struct CanPlantOptions {
  std::string transport;  // after "can:"
  std::string console = "stdio";
  bool realtime = false;
  std::string csv;
  std::string nvm;
};

// Returns the process exit status; throws std::runtime_error with a one-line reason at set-up.
int run_can_plant(const CanPlantOptions& options);

}  // namespace dynweigh::tools
