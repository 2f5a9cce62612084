#pragma once
// The flow as the pac and flowpreact baselines see it, from the display-filtered weight alone (as
// an industrial indicator does): the reading's rise over a window of several platform periods.
// It counts as measured only once the start-up transient is over: the stream has landed (the
// reading is up by a clear step), the valve has finished its stroke, and the display filter has let
// the impact's step through (its derivative, not only its value, settled), and a short window lies
// beyond that; the window then grows to a second.
#include <cstdint>

#include "dynweigh/firmware/parameters.hpp"

namespace dynweigh::firmware {

class DisplayFlowMeter {
 public:
  void configure(const Parameters& parameters);
  void start();
  // One fresh jiffy: the filtered weight added since the open.
  void push(float filled_g);
  bool landed() const { return landed_; }
  bool measured() const { return measured_; }
  // The mean flow over the window ending now (0 before it is measured).
  float flow_kg_s() const { return flow_kg_s_; }

  static constexpr std::uint32_t kHistory = 128;

 private:
  float history_[kHistory] = {};
  std::uint32_t jiffies_ = 0;
  std::uint32_t landing_jiffy_ = 0;
  bool landed_ = false;
  bool measured_ = false;
  float flow_kg_s_ = 0.0f;

  float jiffy_s_ = 0.01f;
  float landing_g_ = 20.0f;
  std::uint32_t blank_jiffies_ = 0;   // from the landing until the transient is over
  std::uint32_t window_jiffies_ = 25;  // the shortest: the flow counts as measured after it
  std::uint32_t longest_window_jiffies_ = 100;
};

}  // namespace dynweigh::firmware
