#include "dynweigh/sim/silo.hpp"

#include <algorithm>
#include <cmath>

#include "dynweigh/model/bore_area.hpp"
#include "dynweigh/model/ideal_model.hpp"

namespace dynweigh::sim {
namespace {

constexpr double kKnotsPerCorrelationTime = 30.0;  // see silo.hpp: rms within 0.8 % between knots

model::BeverlooMaterial<double> material_of(const SiloParameters& p) {
  return {p.beverloo_C, p.beverloo_k, p.grain_d_m, p.bulk_density};
}

}  // namespace

Silo::Silo(const SiloParameters& parameters, double g, std::uint64_t seed)
    : parameters_(parameters),
      table_(material_of(parameters), g, parameters.bore_m),
      bore_area_m2_(model::bore_area_m2(parameters.bore_m)),
      full_open_rate_kg_s_(table_.rate_kg_s(1.0)),
      random_(seed),
      remaining_kg_(parameters.fill_kg),
      alpha_deficit_(1.0 - parameters.alpha_start),
      knot_s_(parameters.fluctuation_correlation_s / kKnotsPerCorrelationTime),
      knot_decay_(std::exp(-1.0 / kKnotsPerCorrelationTime)) {}

double Silo::next_breakpoint_s(double now_s, double limit_s) {
  if (parameters_.fluctuation_rms <= 0.0) return limit_s;
  if (!(now_s >= next_knot_s_ - knot_s_ - 1e-12 && now_s < next_knot_s_ - 1e-12)) {
    next_knot_s_ = (std::floor(now_s / knot_s_ + 1e-9) + 1.0) * knot_s_;  // once per knot
    if (next_knot_s_ - now_s < 1e-12) next_knot_s_ += knot_s_;
  }
  return std::min(next_knot_s_, limit_s);
}

void Silo::move_fluctuation_to_knot(std::int64_t knot) {
  const double rms = parameters_.fluctuation_rms;
  if (knot_ == -2 || knot < knot_) {
    fluctuation_low_ = rms * random_.gaussian();  // the stationary distribution
  } else if (knot == knot_ + 1) {
    fluctuation_low_ = fluctuation_high_;
  } else if (knot > knot_ + 1) {
    // The valve was shut for a while: one exact Ornstein-Uhlenbeck jump over the gap.
    const double decay = std::pow(knot_decay_, double(knot - knot_ - 1));
    fluctuation_low_ = fluctuation_high_ * decay + rms * std::sqrt(1.0 - decay * decay) * random_.gaussian();
  } else {
    return;  // already there
  }
  fluctuation_high_ = fluctuation_low_ * knot_decay_ +
                      rms * std::sqrt(1.0 - knot_decay_ * knot_decay_) * random_.gaussian();
  knot_ = knot;
  knot_start_s_ = double(knot) * knot_s_;
}

double Silo::mean_flow_factor(double begin_s, double dt) {
  // Fluctuation over the interval: f(u) = f0 + slope u, u in [0, dt].
  double f0 = 0.0, slope = 0.0;
  if (parameters_.fluctuation_rms > 0.0) {
    double offset = begin_s - knot_start_s_;
    if (knot_ < 0 || offset < -1e-12 || offset >= knot_s_ - 1e-12) {
      move_fluctuation_to_knot(static_cast<std::int64_t>(std::floor(begin_s / knot_s_ + 1e-9)));
      offset = begin_s - knot_start_s_;
    }
    const std::int64_t knot = knot_;
    slope = (fluctuation_high_ - fluctuation_low_) / knot_s_;
    f0 = fluctuation_low_ + slope * offset;
    (void)knot;
  }
  const double plain = 1.0 + f0 + 0.5 * slope * dt;  // mean of 1 + f
  if (alpha_deficit_ < 1e-17) {  // settled: alpha is 1 to the last bit
    alpha_deficit_ = 0.0;
    return std::max(0.0, plain);
  }
  // Mean of (1 - d exp(-u / tau)) (1 + f0 + slope u) over [0, dt], in closed form.
  const double tau = parameters_.alpha_settle_s;
  if (dt != cached_dt_) {
    cached_dt_ = dt;
    const double x = dt / tau;
    cached_alpha_decay_ = std::exp(-x);
    // Mean over the interval of exp(-u/tau), and of u exp(-u/tau) (= tau^2 ((1 - E) - x E) / dt).
    cached_alpha_mean_ = -std::expm1(-x) / x;
    cached_alpha_moment_ = tau * (-std::expm1(-x) - x * cached_alpha_decay_) / x;
  }
  const double decay = cached_alpha_decay_;
  const double deficit_part = alpha_deficit_ * ((1.0 + f0) * cached_alpha_mean_ + slope * cached_alpha_moment_);
  alpha_deficit_ *= decay;
  return std::max(0.0, plain - deficit_part);
}

double Silo::constant_stroke_rate(double stroke) {
  if (stroke != cached_stroke_) {
    cached_stroke_ = stroke;
    cached_rate_ = table_.rate_kg_s(stroke);
    cached_area_fraction_ = model::open_area_fraction(stroke);
  }
  return cached_rate_;
}

Silo::Outflow Silo::discharge(double begin_s, double stroke_begin, double stroke_end, double dt) {
  ++steps_;
  const bool flowing = stroke_begin > 0.0 || stroke_end > 0.0;
  if (!flowing || remaining_kg_ <= 0.0 || dt <= 0.0) {
    // The bed comes to rest: the next opening settles again.
    if (!flowing) alpha_deficit_ = parameters_.alpha_settle_s > 0.0 ? 1.0 - parameters_.alpha_start : 0.0;
    return {0.0, 0.0};
  }
  if (parameters_.alpha_settle_s <= 0.0) alpha_deficit_ = 0.0;
  double rate = 0.0, area_fraction = 0.0;
  if (stroke_begin == stroke_end) {
    rate = constant_stroke_rate(stroke_begin);
    area_fraction = cached_area_fraction_;
  } else {
    rate = table_.mean_rate_kg_s(stroke_begin, stroke_end);
    area_fraction = 0.5 * (model::open_area_fraction(stroke_begin) + model::open_area_fraction(stroke_end));
  }
  double mass = rate * mean_flow_factor(begin_s, dt) * dt;
  if (mass <= 0.0 || area_fraction <= 0.0) return {0.0, 0.0};
  if (remaining_kg_ - mass < 1e-12) mass = remaining_kg_;  // runs empty: the rest, no residue
  remaining_kg_ -= mass;
  return {mass, model::outflow_speed(mass / dt, bore_area_m2_ * area_fraction, parameters_.bulk_density)};
}

}  // namespace dynweigh::sim
