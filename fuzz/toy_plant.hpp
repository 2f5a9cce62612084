#pragma once
// The smallest plant that lets the console fuzzer's commands run to their end: a valve with a dead
// time and a stroke, a constant flow through it, material landing a fall time later, and a load
// cell with a little dither. Not physics (sim/ is): fast and deterministic, so a fuzz input
// replays the same way every time.
#include <cstdint>

#include "dynweigh/hal/ports.hpp"

namespace dynweigh::fuzz {

class ToyPlant final : public hal::LoadCellPort, public hal::ValvePort {
 public:
  static constexpr float kEmptyCounts = 200000.0f;
  static constexpr float kCountsPerGram = 20.0f;
  static constexpr float kFullFlowGPerJiffy = 40.0f;   // 4 kg/s at full open
  static constexpr int kDeadJiffies = 3;               // the valve's parameter default: 30 ms
  static constexpr int kStrokeJiffies = 8;             // ... and 80 ms
  static constexpr int kFallJiffies = 45;              // about 1 m of free fall

  // One jiffy of the plant, after the indicator's command for it.
  void advance();

  firmware::LoadCellInput read_sample() override;
  void command(firmware::ValveCommand command, std::uint8_t delay_100us) override;
  firmware::ValvePosition position() const override;

 private:
  float target_opening() const;

  firmware::ValveCommand commanded_ = firmware::ValveCommand::closed;
  int jiffies_since_command_ = 0;
  float opening_ = 0.0f;          // 0 closed .. 1 open
  float start_opening_ = 0.0f;    // where the stroke began
  float in_flight_g_[kFallJiffies] = {};
  int flight_index_ = 0;
  float static_g_ = 0.0f;
  std::uint16_t counter_ = 0;
  std::uint32_t dither_ = 12345;
};

}  // namespace dynweigh::fuzz
