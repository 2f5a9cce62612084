#pragma once
#include "dynweigh/schema/can_values.hpp"

namespace dynweigh::sim {

// What the indicator asks of the valve module and what the module reports back: the plant link's
// own values (docs/can-protocol.md).
using schema::ValveCommand;
using schema::ValvePosition;

inline double stroke_for(ValveCommand command) {
  switch (command) {
    case ValveCommand::open: return 1.0;
    case ValveCommand::half: return 0.5;
    case ValveCommand::closed: break;
  }
  return 0.0;
}

}  // namespace dynweigh::sim
