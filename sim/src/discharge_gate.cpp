#include "dynweigh/sim/discharge_gate.hpp"

#include <algorithm>

namespace dynweigh::sim {

double DischargeGate::advance(double dt) {
  const double before = stroke_;
  if (jammed_ || stroke_ == target_) return before;
  if (parameters_.stroke_s <= 0.0) {
    stroke_ = target_;
    return stroke_;
  }
  const double travel = dt / parameters_.stroke_s;
  const double distance = target_ - stroke_;
  const double moved = std::min(travel, distance > 0.0 ? distance : -distance);
  stroke_ += distance > 0.0 ? moved : -moved;
  if (moved >= travel) return 0.5 * (before + stroke_);
  // It reached its end inside the interval: the mean of the ramp and the rest at the end.
  const double ramp_fraction = moved / travel;
  return ramp_fraction * 0.5 * (before + stroke_) + (1.0 - ramp_fraction) * stroke_;
}

GateFeedback DischargeGate::feedback() const {
  if (stroke_ <= 0.0) return GateFeedback::closed;
  if (stroke_ >= 1.0) return GateFeedback::open;
  return GateFeedback::moving;
}

}  // namespace dynweigh::sim
