#include "dynweigh/firmware/valve_timing.hpp"

namespace dynweigh::firmware {
namespace {
bool is_end_position(ValvePosition p) { return p == ValvePosition::closed || p == ValvePosition::open; }
}  // namespace

void ValveTimingMonitor::forget() {
  tracking_ = false;
  timing_dead_ = false;
  for (int d = 0; d < kDirections; ++d) {
    next_[d] = count_[d] = 0;
    mean_motion_ms_[d] = 0.0f;
  }
  for (int d = 0; d < 2; ++d) dead_next_[d] = dead_count_[d] = 0;
}

void ValveTimingMonitor::start_stroke(ValveCommand previous, ValveCommand command, float command_delay_ms) {
  // Only a full stroke from where the feedback last stood still: a half stroke, or a reversal
  // half-way, takes less time and would teach a limit too tight. After a half command the valve is
  // at half or on its way there, whatever end position its feedback last showed (a module
  // with limit switches alone may show none at half): a close or an open from there is no full stroke.
  // A stroke from closed to half is timed apart (`to_half`), and only where the feedback shows half.
  tracking_ = false;
  const bool from_end_position = previous != ValveCommand::half;
  if (from_end_position && command == ValveCommand::open && end_position_ == ValvePosition::closed) {
    from_ = ValvePosition::closed;
    to_ = ValvePosition::open;
    tracking_ = true;
  } else if (from_end_position && command == ValveCommand::closed && end_position_ == ValvePosition::open) {
    from_ = ValvePosition::open;
    to_ = ValvePosition::closed;
    tracking_ = true;
  } else if (previous == ValveCommand::closed && command == ValveCommand::half && end_position_ == ValvePosition::closed) {
    from_ = ValvePosition::closed;
    to_ = ValvePosition::half;
    tracking_ = true;
  }
  delay_ms_ = command_delay_ms;
  age_ = 0;
  leave_age_ = 0;
}

void ValveTimingMonitor::observe(ValveCommand command, float command_delay_ms, ValvePosition position) {
  // What the feedback shows in the jiffy of a new command is the old command's doing: a close that
  // follows the opening's first `moving` at once leaves the opening's dead time timed.
  time_dead(position);
  if (position != ValvePosition::moving) rest_position_ = position;
  last_position_ = position;
  if (command != last_command_) {
    const ValveCommand previous = last_command_;
    last_command_ = command;
    start_stroke(previous, command, command_delay_ms);
    start_dead_time(command);
  }
  if (is_end_position(position)) end_position_ = position;
  if (!tracking_) return;
  ++age_;
  if (leave_age_ == 0 && position != from_) leave_age_ = age_;
  if (position == to_) {
    // Within the jiffy of the command: feedback that echoes it, or a valve that was there already.
    if (age_ > 1) remember(to_ == ValvePosition::open ? opening : (to_ == ValvePosition::half ? to_half : closing));
    tracking_ = false;
  } else if (position != from_ && position != ValvePosition::moving) {
    tracking_ = false;  // somewhere else (half): not this stroke
  }
}

namespace {
ValvePosition position_of(ValveCommand command) {
  return command == ValveCommand::open ? ValvePosition::open
         : command == ValveCommand::half ? ValvePosition::half
                                         : ValvePosition::closed;
}
int openness(ValvePosition p) { return p == ValvePosition::open ? 2 : p == ValvePosition::half ? 1 : 0; }
}  // namespace

// Timed from standstill only: a valve already moving (a close given mid-stroke) shows no dead time.
void ValveTimingMonitor::start_dead_time(ValveCommand command) {
  timing_dead_ = false;
  const ValvePosition to = position_of(command);
  if (last_position_ == ValvePosition::moving || rest_position_ == to) return;
  timing_dead_ = true;
  dead_age_ = 1;  // this jiffy, as a full stroke counts it
  dead_direction_ = openness(to) > openness(rest_position_) ? opening : closing;
}

void ValveTimingMonitor::time_dead(ValvePosition position) {
  if (!timing_dead_) return;
  ++dead_age_;
  if (position == rest_position_) return;
  timing_dead_ = false;
  // Straight to another position (limit switches only, an echo of the command): no dead time shown.
  if (position != ValvePosition::moving) return;
  const Direction d = dead_direction_;
  dead_ms_[d][dead_next_[d]] = float(dead_age_) * jiffy_ms_ - delay_ms_;
  dead_next_[d] = (dead_next_[d] + 1) % kMemory;
  if (dead_count_[d] < kMemory) ++dead_count_[d];
}

float ValveTimingMonitor::slowest_dead_ms(Direction d) const {
  float slowest = 0.0f;
  for (std::uint32_t i = 0; i < dead_count_[d]; ++i) slowest = dead_ms_[d][i] > slowest ? dead_ms_[d][i] : slowest;
  return slowest;
}

void ValveTimingMonitor::remember(Direction d) {
  Stroke& s = strokes_[d][next_[d]];
  s.leave_bound_ms = float(leave_age_) * jiffy_ms_ - delay_ms_;
  s.arrival_bound_ms = float(age_) * jiffy_ms_ - delay_ms_;
  s.arrival_mean_ms = (float(age_) - 0.5f) * jiffy_ms_ - delay_ms_;
  next_[d] = (next_[d] + 1) % kMemory;
  if (count_[d] < kMemory) ++count_[d];
  update_mean_motion(d);
}

float ValveTimingMonitor::slowest_leave_ms(Direction d) const {
  float slowest = 0.0f;
  for (std::uint32_t i = 0; i < count_[d]; ++i) {
    slowest = strokes_[d][i].leave_bound_ms > slowest ? strokes_[d][i].leave_bound_ms : slowest;
  }
  return slowest;
}

float ValveTimingMonitor::slowest_arrival_ms(Direction d) const {
  float slowest = 0.0f;
  for (std::uint32_t i = 0; i < count_[d]; ++i) {
    slowest = strokes_[d][i].arrival_bound_ms > slowest ? strokes_[d][i].arrival_bound_ms : slowest;
  }
  return slowest;
}

float ValveTimingMonitor::mean_arrival_ms(Direction d) const {
  if (count_[d] == 0) return 0.0f;
  float sum = 0.0f;
  for (std::uint32_t i = 0; i < count_[d]; ++i) sum += strokes_[d][i].arrival_mean_ms;
  return sum / float(count_[d]);
}

// Worked out once a stroke ends, not each jiffy it is asked for: the valve's opening jiffy is the
// Cortex-M's heaviest.
void ValveTimingMonitor::update_mean_motion(Direction d) {
  float sum = 0.0f;
  std::uint32_t moving = 0;
  for (std::uint32_t i = 0; i < count_[d]; ++i) {
    const float motion_ms = strokes_[d][i].arrival_bound_ms - strokes_[d][i].leave_bound_ms;
    if (motion_ms > 0.0f) {
      sum += motion_ms;
      ++moving;
    }
  }
  mean_motion_ms_[d] = moving > 0 ? sum / float(moving) : 0.0f;
}

}  // namespace dynweigh::firmware
