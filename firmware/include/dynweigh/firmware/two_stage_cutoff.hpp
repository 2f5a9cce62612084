#pragma once
// The twostage baseline, as industrial filling controllers (SIWAREX, Minebea) do it, on the display-
// filtered weight and its own learned numbers only, never the model's physics:
//  - coarse (full open) until the reading plus the coarse stream's overrun reaches the target minus
//    the fine preact and the fine band (the overrun: how far the reading rose after the switch until
//    the fine stream had landed and the display settled, as the last fills measured it),
//  - fine (half open), the cutoff blanked until the reduced stream has landed (the reading still
//    rises at the full rate for a fall time after the switch, then drops by the lost impulse) and
//    the display filter has settled,
//  - close when the reading reaches the target minus the fine preact.
// After each certified fill the fine preact takes half the error (either sign) and the coarse
// overrun half of what this fill measured: both adapt, so the defaults only set the first fill.
#include <cstdint>

#include "dynweigh/firmware/io.hpp"
#include "dynweigh/firmware/parameters.hpp"

namespace dynweigh::firmware {

class TwoStageCutoff {
 public:
  void configure(const Parameters& parameters);
  // `target_g` net, at the moment the valve opens.
  void start(float target_g);
  // One fresh jiffy with the filtered weight since the start: the valve command it wants now
  // (closed: cut off).
  ValveCommand step(float filled_g);
  // The weight the close compares against the target (the console's prediction).
  float prediction_g() const { return prediction_g_; }
  // After a certified fill of `final_g` grams: the preact and coarse overrun for the next fill.
  void learn(float final_g);
  float fine_preact_g() const { return fine_preact_g_; }
  float coarse_g() const { return coarse_g_; }

 private:
  enum class Stage : std::uint8_t { coarse, fine_blanked, fine, closed };
  float slope_g_s(std::uint32_t jiffies) const;
  void switch_to_fine(float filled_g);
  bool fine_stream_settled(float filled_g);

  static constexpr std::uint32_t kHistory = 32;
  float history_[kHistory] = {};
  std::uint32_t jiffies_ = 0;

  float jiffy_s_ = 0.01f;
  float band_g_ = 0.0f;
  float fine_preact_g_ = 0.0f;
  float coarse_g_ = 0.0f;
  float settle_s_ = 0.0f;

  Stage stage_ = Stage::closed;
  float target_g_ = 0.0f;
  float prediction_g_ = 0.0f;
  float coarse_rate_g_s_ = 0.0f;
  float switch_weight_g_ = 0.0f;
  std::uint32_t switch_jiffy_ = 0;
  std::uint32_t dip_jiffy_ = 0;
  bool dipped_ = false;
  bool measured_overrun_ = false;
  float overrun_g_ = 0.0f;
};

}  // namespace dynweigh::firmware
