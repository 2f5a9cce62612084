#include "dynweigh/sim/pneumatic_valve.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace dynweigh::sim {

PneumaticValve::PneumaticValve(const ValveParameters& parameters, std::uint64_t seed)
    : parameters_(parameters), random_(seed) {}

void PneumaticValve::command(ValveCommand target, double issued_s) {
  const double jitter = parameters_.dead_time_jitter_s > 0.0
                            ? parameters_.dead_time_jitter_s * random_.gaussian()
                            : 0.0;
  const double start = std::max(issued_s, issued_s + parameters_.dead_time_s + jitter);
  if (pending_count_ == kQueue) {  // a command storm: the newest wish wins over the oldest
    std::move(pending_.begin() + 1, pending_.end(), pending_.begin());
    --pending_count_;
  }
  // Air pressure is not a queue: a later command that starts no later replaces earlier ones.
  while (pending_count_ > 0 && pending_[pending_count_ - 1].start_s >= start) --pending_count_;
  pending_[pending_count_++] = {start, stroke_for(target)};
  start_due_commands();
}

ValvePosition PneumaticValve::feedback() const {
  if (stroke_ != target_) return ValvePosition::moving;
  if (stroke_ <= 0.0) return ValvePosition::closed;
  if (stroke_ >= 1.0) return ValvePosition::open;
  return ValvePosition::half;
}

double PneumaticValve::next_breakpoint_s(double limit_s) const {
  double next = limit_s;
  if (pending_count_ > 0) next = std::min(next, std::max(now_s_, pending_[0].start_s));
  if (stroke_ != target_ && parameters_.full_stroke_s > 0.0) {
    next = std::min(next, now_s_ + std::abs(target_ - stroke_) * parameters_.full_stroke_s);
  }
  return next;
}

void PneumaticValve::start_due_commands() {
  std::size_t due = 0;
  while (due < pending_count_ && pending_[due].start_s <= now_s_) {
    target_ = pending_[due].target;
    ++due;
  }
  if (due > 0) {
    std::move(pending_.begin() + static_cast<std::ptrdiff_t>(due),
              pending_.begin() + static_cast<std::ptrdiff_t>(pending_count_), pending_.begin());
    pending_count_ -= due;
  }
  if (parameters_.full_stroke_s <= 0.0) stroke_ = target_;
}

void PneumaticValve::advance_to(double time_s) {
  // Callers step between breakpoints, so the slope is constant over [now, time].
  ++steps_;
  const double elapsed = time_s - now_s_;
  if (stroke_ != target_ && parameters_.full_stroke_s > 0.0 && elapsed > 0.0) {
    const double travel = elapsed / parameters_.full_stroke_s;
    stroke_ = stroke_ < target_ ? std::min(target_, stroke_ + travel)
                                : std::max(target_, stroke_ - travel);
    // Snap floating residue at the end of a stroke so feedback reports the end position.
    if (std::abs(stroke_ - target_) < 1e-12) stroke_ = target_;
  }
  now_s_ = time_s;
  start_due_commands();
}

}  // namespace dynweigh::sim
