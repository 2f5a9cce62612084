#pragma once
// How far a material's measured closes came out from their predictions, in standard deviations of
// the uncertainty the plan gave each of them (dose_plan.hpp): the mean square of the last few, kept
// with the material. The plan's uncertainty for a measured close is a model (the landing rate's
// fluctuation, the estimator's share, the let-through not yet shown); on the plant family its
// closes came out within about three quarters of it, because the rate a dose reads fluctuates more
// than the flow does (the load cell's noise and the platform's ringing are in it). A material whose
// closes showed it scales the next dose's uncertainty, and so its margin and how often a top-up
// is needed; a material whose closes came out wider than the model said widens it.
// The scale leans on the model until closes have shown otherwise: the model's own uncertainty
// counts as kPriorCloses closes that came out at one sigma, so that however close the last kMemory
// closes came out, the scale stays above sqrt(4 / 12) = 0.58: a few closes say little of a tail.
// It stays below kHighestScale: a material whose closes scatter far more than its model says is
// better served by the rest of the plan (the top-ups) than by a margin that grows without end.
#include <cmath>
#include <cstdint>

namespace dynweigh::firmware {

class MeasuredCloseSpread {
 public:
  static constexpr float kMemory = 8.0f;         // closes the mean square follows
  static constexpr float kPriorCloses = 4.0f;    // the model's uncertainty weighs as these closes
  static constexpr float kLargestSquare = 9.0f;  // one close counts at most as three sigmas off
  static constexpr float kHighestScale = 1.5f;

  // A certified measured close, `error_sigmas` = (final - prediction) / the plan's sigma for it.
  void add(float error_sigmas) {
    if (!std::isfinite(error_sigmas)) return;
    const float square = std::fmin(error_sigmas * error_sigmas, kLargestSquare);
    const float n = std::fmin(float(closes_) + 1.0f, kMemory);
    mean_square_ += (square - mean_square_) / n;
    if (closes_ < 0xFF) ++closes_;
  }

  // What the next measured close's uncertainty is multiplied by: 1 until closes have shown it.
  float sigma_scale() const {
    const float n = std::fmin(float(closes_), kMemory);
    const float scale = std::sqrt((kPriorCloses + n * mean_square_) / (kPriorCloses + n));
    return std::fmin(kHighestScale, scale);
  }

  float mean_square() const { return mean_square_; }
  std::uint8_t closes() const { return closes_; }

  // The settings record's view: false (and nothing learned) for what add() cannot make.
  bool restore(float mean_square, std::uint8_t closes) {
    const bool sane = std::isfinite(mean_square) && mean_square >= 0.0f && mean_square <= kLargestSquare;
    mean_square_ = sane && closes > 0 ? mean_square : 0.0f;
    closes_ = sane ? closes : 0;
    return sane;
  }

 private:
  float mean_square_ = 0.0f;
  std::uint8_t closes_ = 0;
};

}  // namespace dynweigh::firmware
