#pragma once
// Least-squares line through the last N samples (one per jiffy). Evaluated at the newest sample
// it estimates the present reading without a low-pass filter's lag, and its slope is the flow.
// Samples are stored relative to the oldest kept one so float keeps resolution at full scale.
#include <cstddef>

namespace dynweigh::model {

template <typename Scalar, std::size_t Capacity>
class SlidingLineFit {
 public:
  static_assert(Capacity >= 2, "a line needs two points");

  void reset() { count_ = 0; head_ = 0; }

  void set_window(std::size_t samples) {
    window_ = samples < 2 ? 2 : (samples > Capacity ? Capacity : samples);
    reset();
  }
  std::size_t window() const { return window_; }
  std::size_t count() const { return count_; }
  bool full() const { return count_ == window_; }

  void push(Scalar value) {
    samples_[head_] = value;
    head_ = (head_ + 1) % window_;
    if (count_ < window_) ++count_;
  }

  // Slope per sample and value at the newest sample, by centred least squares.
  struct Line {
    Scalar slope_per_sample;
    Scalar value_at_newest;
  };
  Line fit() const {
    const std::size_t n = count_;
    if (n < 2) return {Scalar(0), n ? at(0) : Scalar(0)};
    const Scalar reference = at(0);
    const Scalar centre = Scalar(n - 1) / Scalar(2);
    Scalar sum_y = 0, sum_xy = 0, sum_xx = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const Scalar x = Scalar(i) - centre;
      const Scalar y = at(i) - reference;
      sum_y += y;
      sum_xy += x * y;
      sum_xx += x * x;
    }
    const Scalar slope = sum_xy / sum_xx;
    return {slope, reference + sum_y / Scalar(n) + slope * centre};
  }

 private:
  // i = 0 is the oldest sample kept.
  Scalar at(std::size_t i) const {
    const std::size_t oldest = (head_ + window_ - count_) % window_;
    return samples_[(oldest + i) % window_];
  }

  Scalar samples_[Capacity] = {};
  std::size_t window_ = Capacity;
  std::size_t count_ = 0;
  std::size_t head_ = 0;
};

}  // namespace dynweigh::model
