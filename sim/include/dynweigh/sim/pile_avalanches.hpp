#pragma once
// Avalanches on the pile's slope (thesis §3.2 and example 3.2): the mass added at the top since
// the last avalanche is the deciding factor; when it exceeds the critical mass an avalanche runs,
// and the pattern repeats because the top returns to the same state after each one. Its duration
// grows with the slope it runs down (a larger pile, a longer avalanche).
//
// Force: material starts at rest on the slope and ends at rest at its foot, so the momentum the
// scale takes over is zero: it feels a dip of -F_a while the mass accelerates (first half) and a
// push of +F_a while it is stopped (second half). The thesis' "F_imp + F_a" is the second half.
// The step's mean force is computed from the exact overlaps, so the impulse balance holds at any
// step size.
#include <array>
#include <cstddef>
#include <cstdint>

#include "dynweigh/sim/scene.hpp"

namespace dynweigh::sim {

class PileAvalanches {
 public:
  explicit PileAvalanches(const AvalancheParameters& parameters) : parameters_(parameters) {}

  // Adds the mass landed on the top during [begin_s, end_s] and returns the mean avalanche force
  // over that step. `slope_fraction` is the slope's length relative to the full container's.
  double step(double landed_kg, double slope_fraction, double begin_s, double end_s);

  std::uint64_t avalanches() const { return started_; }
  std::uint64_t steps() const { return steps_; }
  double added_since_last_kg() const { return added_kg_; }

 private:
  struct Running {
    double start_s;
    double duration_s;
  };
  static constexpr std::size_t kMaxRunning = 32;  // beyond this, the next waits for a free slot
  AvalancheParameters parameters_;
  std::array<Running, kMaxRunning> running_{};
  std::size_t running_count_ = 0;
  double added_kg_ = 0.0;
  std::uint64_t started_ = 0;
  std::uint64_t steps_ = 0;
};

}  // namespace dynweigh::sim
