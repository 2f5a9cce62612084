#pragma once
// The silo and its orifice: Beverloo's rate through the gate's open area (independent of the fill
// level, Janssen), scaled by the start-up settling alpha(t) (thesis eq. 3.16) and a seeded,
// correlated fluctuation (docs/scenes.md). The fill level matters only when the silo runs empty.
//
// Every term is integrated exactly over a step, so the let-through converges as the step shrinks:
// - the stroke's effect through a set-up table (stroke_discharge_table.hpp);
// - alpha(t) = 1 - (1 - alpha_start) exp(-t / alpha_settle_s) after each opening, in closed form;
// - the fluctuation is an Ornstein-Uhlenbeck process sampled exactly on a fixed grid of knots
//   (1/30 of its correlation time) and linear between them, so its path does not depend on the
//   plant's step; the caller splits steps at the knots (next_breakpoint_s). Linear interpolation
//   lowers the rms between knots by at most 0.8 % (variance (1 + exp(-1/30)) / 2 at mid-knot).
// The only step-dependent error left is the product of a moving stroke with alpha and the
// fluctuation, taken as the product of their means: second order in the step, during strokes.
#include <cstdint>

#include "dynweigh/model/beverloo.hpp"
#include "dynweigh/sim/random.hpp"
#include "dynweigh/sim/scene.hpp"
#include "dynweigh/sim/stroke_discharge_table.hpp"

namespace dynweigh::sim {

class Silo {
 public:
  Silo(const SiloParameters& parameters, double g, std::uint64_t seed);

  struct Outflow {
    double mass_kg;
    double speed_m_s;
  };
  // Mass that leaves over [begin_s, begin_s + dt] while the stroke moves linearly from
  // `stroke_begin` to `stroke_end`, and its outflow speed v0. The interval must not contain a
  // fluctuation knot (split at next_breakpoint_s).
  Outflow discharge(double begin_s, double stroke_begin, double stroke_end, double dt);

  // The next fluctuation knot after `now_s`, or `limit_s` if that comes first.
  double next_breakpoint_s(double now_s, double limit_s);

  double remaining_kg() const { return remaining_kg_; }
  // Material poured in from upstream (the level does not change the rate: Janssen).
  void add(double kg) { remaining_kg_ += kg; }
  double full_open_rate_kg_s() const { return full_open_rate_kg_s_; }
  double rate_at_stroke_kg_s(double stroke) const { return table_.rate_kg_s(stroke); }
  std::uint64_t steps() const { return steps_; }

 private:
  double constant_stroke_rate(double stroke);
  double mean_flow_factor(double begin_s, double dt);
  void move_fluctuation_to_knot(std::int64_t knot);

  SiloParameters parameters_;
  StrokeDischargeTable table_;
  double bore_area_m2_;
  double full_open_rate_kg_s_;
  Random random_;
  double remaining_kg_;
  double alpha_deficit_;  // 1 - alpha
  // Cache of the exponential over the last interval length (almost always the plant's step).
  double cached_dt_ = -1.0;
  double cached_alpha_decay_ = 1.0;
  double cached_alpha_mean_ = 0.0;
  double cached_alpha_moment_ = 0.0;
  double cached_stroke_ = -1.0;
  double cached_rate_ = 0.0;
  double cached_area_fraction_ = 0.0;
  // Fluctuation knots.
  double knot_s_;
  double knot_decay_;
  std::int64_t knot_ = -2;  // index of fluctuation_low_; -2: no knot drawn yet
  double fluctuation_low_ = 0.0;
  double fluctuation_high_ = 0.0;
  double knot_start_s_ = 0.0;
  double next_knot_s_ = -1.0;  // cached: the next knot after the last query
  std::uint64_t steps_ = 0;
};

}  // namespace dynweigh::sim
