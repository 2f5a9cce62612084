#include "dynweigh/sim/silo.hpp"

#include <algorithm>
#include <cmath>

#include "dynweigh/model/bore_area.hpp"
#include "dynweigh/model/ideal_model.hpp"

namespace dynweigh::sim {

Silo::Silo(const SiloParameters& parameters, double g, std::uint64_t seed)
    : parameters_(parameters),
      material_{parameters.beverloo_C, parameters.beverloo_k, parameters.grain_d_m,
                parameters.bulk_density},
      g_(g),
      random_(seed),
      remaining_kg_(parameters.fill_kg),
      alpha_(parameters.alpha_start) {
  if (parameters_.fluctuation_rms > 0.0) fluctuation_ = parameters_.fluctuation_rms * random_.gaussian();
}

double Silo::rate_at(double stroke) const {
  return model::discharge_at_stroke_kg_s(material_, g_, parameters_.bore_m, stroke);
}

double Silo::full_open_rate_kg_s() const { return rate_at(1.0); }

void Silo::update_disturbances(bool flowing, double dt) {
  if (!flowing) {
    alpha_ = parameters_.alpha_start;  // the bed comes to rest: the next opening settles again
  } else if (parameters_.alpha_settle_s > 0.0) {
    alpha_ += (1.0 - alpha_) * -std::expm1(-dt / parameters_.alpha_settle_s);
  } else {
    alpha_ = 1.0;
  }
  if (parameters_.fluctuation_rms > 0.0 && parameters_.fluctuation_correlation_s > 0.0) {
    // Exact Ornstein-Uhlenbeck update: the rms and correlation time hold at any step size.
    const double decay = std::exp(-dt / parameters_.fluctuation_correlation_s);
    fluctuation_ = fluctuation_ * decay +
                   parameters_.fluctuation_rms * std::sqrt(1.0 - decay * decay) * random_.gaussian();
  }
}

Silo::Outflow Silo::discharge(double stroke_begin, double stroke_end, double dt) {
  const bool flowing = stroke_begin > 0.0 || stroke_end > 0.0;
  const double mean_rate = 0.5 * (rate_at(stroke_begin) + rate_at(stroke_end));
  const double factor = std::max(0.0, alpha_ * (1.0 + fluctuation_));
  double mass = std::min(remaining_kg_, mean_rate * factor * dt);
  update_disturbances(flowing, dt);
  if (mass <= 0.0) return {0.0, 0.0};
  remaining_kg_ -= mass;
  const double mean_area =
      model::bore_area_m2(parameters_.bore_m) *
      0.5 * (model::open_area_fraction(stroke_begin) + model::open_area_fraction(stroke_end));
  return {mass, model::outflow_speed(mass / dt, mean_area, parameters_.bulk_density)};
}

}  // namespace dynweigh::sim
