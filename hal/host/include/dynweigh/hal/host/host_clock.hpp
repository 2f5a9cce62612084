#pragma once
// The host's jiffy: lockstep (returns at once, the plant's time is the only time) or real time
// (sleeps to the next 10 ms boundary of the wall clock, and counts the periods it missed).
#include <chrono>
#include <cstdint>
#include <thread>

#include "dynweigh/hal/ports.hpp"

namespace dynweigh::hal::host {

class HostClock final : public JiffyClock {
 public:
  explicit HostClock(bool realtime, std::chrono::milliseconds period = std::chrono::milliseconds(10))
      : realtime_(realtime), period_(period), start_(std::chrono::steady_clock::now()) {}

  bool wait_next_jiffy() override {
    ++jiffy_;
    if (!realtime_) return true;
    const auto due = start_ + period_ * jiffy_;
    if (std::chrono::steady_clock::now() > due + period_) ++missed_;
    std::this_thread::sleep_until(due);
    return true;
  }
  std::uint32_t jiffy() const override { return jiffy_; }
  std::uint32_t missed_periods() const { return missed_; }

 private:
  bool realtime_;
  std::chrono::milliseconds period_;
  std::chrono::steady_clock::time_point start_;
  std::uint32_t jiffy_ = 0;
  std::uint32_t missed_ = 0;
};

}  // namespace dynweigh::hal::host
