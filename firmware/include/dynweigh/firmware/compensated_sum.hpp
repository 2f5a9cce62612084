#pragma once
// A running sum of floats kept to about twice float's precision (Knuth's two-sum): the error of each
// addition is exact in float and collected apart. The M4F has no double, and a plain float sum of a
// window of weights loses the last grams' digits.
#include <cmath>
#include <cstdint>

namespace dynweigh::firmware {

class CompensatedSum {
 public:
  void reset() { high_ = low_ = 0.0f; }

  void add(float value) {
    const float sum = high_ + value;
    const float value_part = sum - high_;
    const float error = (high_ - (sum - value_part)) + (value - value_part);
    high_ = sum;
    low_ += error;
  }

  // The sum over `count`, rounded once from the two parts (fma: the remainder of high / count exactly).
  float mean(std::uint32_t count) const {
    if (count == 0) return 0.0f;
    const float n = float(count);
    const float quotient = high_ / n;
    const float remainder = std::fma(-quotient, n, high_);
    return quotient + (remainder + low_) / n;
  }

 private:
  float high_ = 0.0f, low_ = 0.0f;
};

}  // namespace dynweigh::firmware
