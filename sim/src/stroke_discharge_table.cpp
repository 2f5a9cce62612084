#include "dynweigh/sim/stroke_discharge_table.hpp"

#include <algorithm>
#include <cmath>

#include "dynweigh/model/bore_area.hpp"

namespace dynweigh::sim {

StrokeDischargeTable::StrokeDischargeTable(const model::BeverlooMaterial<double>& material, double g, double bore_m)
    : material_(material), g_(g), bore_m_(bore_m), integral_(kIntervals + 1), rate_(kIntervals + 1) {
  // Gauss-Legendre, 5 points per interval: the rate is smooth but where the equivalent diameter
  // passes k d (the orifice stops arching), and there the interval is only 1/128 of the stroke.
  static constexpr double kNodes[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831,
                                       0.9061798459386640};
  static constexpr double kWeights[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                                         0.4786286704993665, 0.2369268850561891};
  const double width = 1.0 / kIntervals;
  integral_[0] = 0.0;
  rate_[0] = rate_kg_s(0.0);
  for (int i = 0; i < kIntervals; ++i) {
    const double centre = (i + 0.5) * width;
    double sum = 0.0;
    for (int q = 0; q < 5; ++q) sum += kWeights[q] * rate_kg_s(centre + 0.5 * width * kNodes[q]);
    integral_[i + 1] = integral_[i] + 0.5 * width * sum;
    rate_[i + 1] = rate_kg_s((i + 1) * width);
  }
}

double StrokeDischargeTable::rate_kg_s(double stroke) const {
  return model::discharge_at_stroke_kg_s(material_, g_, bore_m_, stroke);
}

double StrokeDischargeTable::cumulative(double stroke) const {
  const double s = std::clamp(stroke, 0.0, 1.0) * kIntervals;
  const int i = std::min(kIntervals - 1, static_cast<int>(s));
  const double t = s - i;
  const double width = 1.0 / kIntervals;
  // Cubic Hermite on [s_i, s_i+1] with end values I and end slopes rate.
  const double t2 = t * t, t3 = t2 * t;
  const double h00 = 2 * t3 - 3 * t2 + 1, h10 = t3 - 2 * t2 + t, h01 = -2 * t3 + 3 * t2, h11 = t3 - t2;
  return h00 * integral_[i] + h10 * width * rate_[i] + h01 * integral_[i + 1] + h11 * width * rate_[i + 1];
}

double StrokeDischargeTable::mean_rate_kg_s(double stroke_begin, double stroke_end) const {
  const double span = stroke_end - stroke_begin;
  if (std::abs(span) < 1e-9) return rate_kg_s(0.5 * (stroke_begin + stroke_end));
  return (cumulative(stroke_end) - cumulative(stroke_begin)) / span;
}

}  // namespace dynweigh::sim
