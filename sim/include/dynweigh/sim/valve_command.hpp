#pragma once
#include <cstdint>

namespace dynweigh::sim {

// What the indicator asks of the valve module (docs/can-protocol.md: 0 closed, 1 half, 2 open).
enum class ValveCommand : std::uint8_t { closed = 0, half = 1, open = 2 };

// What the valve module reports back (docs/can-protocol.md: 0 closed, 1 moving, 2 half, 3 open).
enum class ValveFeedback : std::uint8_t { closed = 0, moving = 1, half = 2, open = 3 };

inline double stroke_for(ValveCommand command) {
  switch (command) {
    case ValveCommand::open: return 1.0;
    case ValveCommand::half: return 0.5;
    case ValveCommand::closed: break;
  }
  return 0.0;
}

}  // namespace dynweigh::sim
