#pragma once
// A pneumatic slide gate: after a dead time (with jitter) the gate moves at a constant speed
// toward the commanded stroke. The stroke is piecewise linear in time; its breakpoints are
// exposed so the silo can integrate the flow exactly between them.
#include <array>
#include <cstddef>
#include <cstdint>

#include "dynweigh/sim/random.hpp"
#include "dynweigh/sim/scene.hpp"
#include "dynweigh/sim/valve_command.hpp"

namespace dynweigh::sim {

class PneumaticValve {
 public:
  PneumaticValve(const ValveParameters& parameters, std::uint64_t seed);

  // The command reaches the actuator at `issued_s`; the gate starts after the dead time.
  void command(ValveCommand target, double issued_s);

  double stroke() const { return stroke_; }
  double time_s() const { return now_s_; }
  ValvePosition feedback() const;

  // The earliest time after now at which the stroke's slope changes (or `limit_s`).
  double next_breakpoint_s(double limit_s) const;
  void advance_to(double time_s);
  std::uint64_t steps() const { return steps_; }
  // No stroke time: the gate jumps at a breakpoint instead of moving linearly up to it.
  bool instant() const { return parameters_.full_stroke_s <= 0.0; }

 private:
  struct Pending {
    double start_s;
    double target;
  };
  void start_due_commands();

  ValveParameters parameters_;
  Random random_;
  double now_s_ = 0.0;
  double stroke_ = 0.0;
  double target_ = 0.0;
  static constexpr std::size_t kQueue = 8;
  std::array<Pending, kQueue> pending_{};
  std::size_t pending_count_ = 0;
  std::uint64_t steps_ = 0;
};

}  // namespace dynweigh::sim
