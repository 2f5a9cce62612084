#pragma once
// The discharge gate under the weigh hopper (CAN node 0x28): opened to empty the hopper, shut
// to fill it. It strokes linearly over GateParameters::stroke_s; its feedback reports closed,
// moving or open as the module's limit switches do. A jammed gate holds where it is whatever it
// is told (for the supervision's tests: a gate that does not open or does not close).
#include <cstdint>

#include "dynweigh/sim/scene.hpp"

namespace dynweigh::sim {

// What the indicator asks of the gate module (0 closed, 2 open: no half position).
enum class GateCommand : std::uint8_t { closed = 0, open = 2 };
// What the gate module reports (0 closed, 1 moving, 3 open).
enum class GateFeedback : std::uint8_t { closed = 0, moving = 1, open = 3 };

class DischargeGate {
 public:
  explicit DischargeGate(const GateParameters& parameters) : parameters_(parameters) {}

  void command(GateCommand command) { target_ = command == GateCommand::open ? 1.0 : 0.0; }
  void jam(bool jammed) { jammed_ = jammed; }
  bool jammed() const { return jammed_; }

  // Moves the gate over `dt`; returns its mean stroke over the interval (0 shut .. 1 open).
  double advance(double dt);

  double stroke() const { return stroke_; }
  GateFeedback feedback() const;

 private:
  GateParameters parameters_;
  double target_ = 0.0;
  double stroke_ = 0.0;
  bool jammed_ = false;
};

}  // namespace dynweigh::sim
