#pragma once
// The valve's timing as its feedback shows it. For every full stroke (closed to open, open to
// closed) the time from the command to the feedback's leaving the old end position, and to its
// reporting the new one, for opening and closing apart (a pneumatic valve fills and exhausts at
// different speeds). A valve whose feedback reports `moving` leaves its end position at its dead
// time; one whose feedback reports end positions only (limit switches) leaves when it arrives.
//
// The feedback is read once a jiffy: an event seen at the n-th jiffy after the command happened
// within the jiffy before, less the part of a jiffy by which the command was delayed (the valve
// module's delay byte). The slowest bounds (n jiffies less the delay) are what the fault supervisor
// allows; the mean of the jiffies' midpoints is what the model cutoff times the close with. A stroke
// that ends in the jiffy of its command times nothing: the feedback echoes the command, or the valve
// was there already.
//
// The dead time alone is also timed on strokes that are not full (closed to half, half to closed, a
// close given while the valve was still opening): from the command to the feedback's first `moving`
// after it stood still. It does not depend on where the stroke goes, and a dose on a fast plant may
// close before the valve ever reached `open`.
//
// A valve whose feedback reports the half position also has its strokes from closed to half timed
// (`to_half`): half the stroke after the dead time. A top-up pulse opens half, and its mass depends
// on how fast the gate gets there; on a fast plant whose doses all close before the valve is open,
// the pulses' own half strokes are the only strokes timed.
#include <cstdint>

#include "dynweigh/firmware/io.hpp"

namespace dynweigh::firmware {

class ValveTimingMonitor {
 public:
  static constexpr std::uint32_t kMemory = 8;  // strokes remembered: a valve that ages is followed

  void configure(float jiffy_ms) { jiffy_ms_ = jiffy_ms; }
  // A new valve, or none: forget every stroke.
  void forget();
  // Each jiffy: the command given last jiffy, how far into its jiffy it acted, the feedback now.
  void observe(ValveCommand command_in_force, float command_delay_ms, ValvePosition position);
  // The stroke under way took longer than a healthy one may: whenever it ends (a valve freed, the
  // plant replaced) it teaches nothing.
  void abandon_stroke() {
    tracking_ = false;
    timing_dead_ = false;
  }

  // Dead times are timed for `opening` and `closing` only (any stroke from standstill).
  enum Direction : std::uint8_t { opening = 0, closing = 1, to_half = 2 };
  std::uint32_t strokes(Direction d) const { return count_[d]; }
  // Over the remembered strokes of one direction, ms from the command's acting: the latest the
  // feedback left its end position, the latest it reported the new one, and the mean time to the new
  // one. 0 before the first.
  float slowest_leave_ms(Direction d) const;
  float slowest_arrival_ms(Direction d) const;
  float mean_arrival_ms(Direction d) const;
  // The mean time the feedback showed the valve moving (from leaving its position to reporting the
  // new one): the stroke without the dead time. 0 before the first, or where the feedback never
  // shows `moving` (limit switches alone).
  float mean_motion_ms(Direction d) const { return mean_motion_ms_[d]; }
  // The dead times timed so far in one direction (any stroke from standstill that showed `moving`),
  // and the latest, ms from the command's acting (0 before the first).
  std::uint32_t dead_times(Direction d) const { return dead_count_[d]; }
  float slowest_dead_ms(Direction d) const;

 private:
  struct Stroke {
    float leave_bound_ms;
    float arrival_bound_ms;
    float arrival_mean_ms;
  };
  void start_stroke(ValveCommand previous, ValveCommand command, float command_delay_ms);
  void remember(Direction d);
  void update_mean_motion(Direction d);
  void start_dead_time(ValveCommand command);
  void time_dead(ValvePosition position);

  float jiffy_ms_ = 10.0f;
  ValveCommand last_command_ = ValveCommand::closed;
  ValvePosition end_position_ = ValvePosition::closed;  // the last end position the feedback reported
  bool tracking_ = false;  // a full stroke (or one from closed to half) is under way
  ValvePosition from_ = ValvePosition::closed;
  ValvePosition to_ = ValvePosition::open;
  float delay_ms_ = 0.0f;
  std::uint32_t age_ = 0;  // jiffies since the command
  std::uint32_t leave_age_ = 0;
  // Dead time: a command that set the valve in motion from where it stood still.
  ValvePosition rest_position_ = ValvePosition::closed;  // the last position other than `moving`
  ValvePosition last_position_ = ValvePosition::closed;
  bool timing_dead_ = false;
  std::uint32_t dead_age_ = 0;  // jiffies since the command
  Direction dead_direction_ = opening;
  float dead_ms_[2][kMemory] = {};
  std::uint32_t dead_next_[2] = {};
  std::uint32_t dead_count_[2] = {};
  static constexpr int kDirections = 3;
  Stroke strokes_[kDirections][kMemory] = {};
  std::uint32_t next_[kDirections] = {};
  std::uint32_t count_[kDirections] = {};
  float mean_motion_ms_[kDirections] = {};
};

}  // namespace dynweigh::firmware
