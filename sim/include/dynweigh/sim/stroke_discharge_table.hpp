#pragma once
// Beverloo's rate against the gate's stroke is far from linear (open area of a round bore, then
// the 5/2 power), so the mass let through while the gate moves is integrated once at set-up:
// I(s) = integral of rate(sigma) d sigma from 0 to s on a grid of 128 intervals, interpolated with cubic
// Hermite using I' = rate. The mean rate over a linear stroke from a to b is then
// (I(b) - I(a)) / (b - a), whatever the step: the plant's let-through does not depend on dt.
#include <vector>

#include "dynweigh/model/beverloo.hpp"

namespace dynweigh::sim {

class StrokeDischargeTable {
 public:
  StrokeDischargeTable(const model::BeverlooMaterial<double>& material, double g, double bore_m);

  double rate_kg_s(double stroke) const;  // exact (no table) — set-up and tests
  // Mean rate while the stroke moves linearly from `stroke_begin` to `stroke_end`.
  double mean_rate_kg_s(double stroke_begin, double stroke_end) const;
  double cumulative(double stroke) const;  // I(s), kg/s times stroke

 private:
  static constexpr int kIntervals = 128;  // Hermite error ~ (1/128)^4 of the rate's curvature
  model::BeverlooMaterial<double> material_;
  double g_;
  double bore_m_;
  std::vector<double> integral_;  // I at s_i = i / kIntervals
  std::vector<double> rate_;      // rate at s_i
};

}  // namespace dynweigh::sim
