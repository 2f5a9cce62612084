#include "dynweigh/hal/can/sample_sequence.hpp"

namespace dynweigh::hal::can {

SampleSequence::Arrival SampleSequence::arrive(std::uint16_t counter) {
  Arrival arrival;
  const std::uint16_t ahead = std::uint16_t(counter - last_);  // modulo 2^16: the counter wraps
  if (started_ && ahead == 0) {
    ++duplicates_;
    return arrival;
  }
  const std::uint16_t behind = std::uint16_t(last_ - counter);
  if (started_ && behind <= kReorderWindow) {
    ++out_of_order_;
    return arrival;
  }
  arrival.accept = true;
  if (started_ && ahead <= kMaxFill) {
    const std::uint32_t gap = std::uint32_t(ahead) - 1u;
    lost_ += gap;
    arrival.missing = std::uint16_t(gap > stood_in_ ? gap - stood_in_ : 0u);
  } else if (started_) {
    ++restarts_;
  }
  started_ = true;
  last_ = counter;
  stood_in_ = 0;
  return arrival;
}

void SampleSequence::stood_in() { ++stood_in_; }

void SampleSequence::reset() {
  started_ = false;
  stood_in_ = 0;
}

}  // namespace dynweigh::hal::can
