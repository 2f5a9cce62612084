#include "toy_plant.hpp"

#include <cmath>

namespace dynweigh::fuzz {

float ToyPlant::target_opening() const {
  switch (commanded_) {
    case firmware::ValveCommand::open: return 1.0f;
    case firmware::ValveCommand::half: return 0.5f;
    case firmware::ValveCommand::closed: break;
  }
  return 0.0f;
}

void ToyPlant::command(firmware::ValveCommand command, std::uint8_t /*delay_100us*/) {
  if (command == commanded_) return;
  commanded_ = command;
  start_opening_ = opening_;
  jiffies_since_command_ = 0;
}

void ToyPlant::advance() {
  ++jiffies_since_command_;
  const int moving = jiffies_since_command_ - kDeadJiffies;
  if (moving > 0) {
    const float progress = moving >= kStrokeJiffies ? 1.0f : float(moving) / float(kStrokeJiffies);
    opening_ = start_opening_ + (target_opening() - start_opening_) * progress;
  }
  // What leaves the orifice now lands kFallJiffies later.
  static_g_ += in_flight_g_[flight_index_];
  in_flight_g_[flight_index_] = opening_ * kFullFlowGPerJiffy;
  flight_index_ = (flight_index_ + 1) % kFallJiffies;
}

firmware::LoadCellInput ToyPlant::read_sample() {
  dither_ = dither_ * 1664525u + 1013904223u;  // a few counts of noise: a live ADC never repeats
  firmware::LoadCellInput sample;
  sample.raw_counts = std::int32_t(std::lround(kEmptyCounts + static_g_ * kCountsPerGram)) + std::int32_t(dither_ >> 30);
  sample.counter = counter_++;
  return sample;
}

firmware::ValvePosition ToyPlant::position() const {
  if (opening_ == 0.0f) return firmware::ValvePosition::closed;
  if (opening_ == 1.0f) return firmware::ValvePosition::open;
  if (opening_ == 0.5f && target_opening() == 0.5f) return firmware::ValvePosition::half;
  return firmware::ValvePosition::moving;
}

}  // namespace dynweigh::fuzz
