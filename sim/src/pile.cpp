#include "dynweigh/sim/pile.hpp"

#include <algorithm>
#include <cmath>

namespace dynweigh::sim {
namespace {
constexpr double kMinimumFallM = 0.001;  // same floor as model::fall_height_to_pile_m
}

Pile::Pile(const ColumnParameters& column, const PileTopParameters* top, double bulk_density)
    : orifice_to_floor_m_(column.fall_height_m),
      slope_(std::tan(column.repose_angle_deg * M_PI / 180.0)),
      container_radius_m_(0.5 * column.container_diameter_m),
      flat_radius_m_(top ? top->flat_radius_m : 0.0),
      bulk_density_(bulk_density) {
  const double rc = container_radius_m_, rf = flat_radius_m_;
  full_volume_m3_ = M_PI / 3.0 * slope_ * (rc * rc * rc - rf * rf * rf);
  if (top) {
    dent_depth_m_ = top->dent_depth_m;
    dent_settle_s_ = top->dent_settle_s;
  }
}

void Pile::update_cache(double mass_kg) {
  ++steps_;
  cached_mass_kg_ = mass_kg;
  const double volume = std::max(0.0, mass_kg) / bulk_density_;
  const double rc = container_radius_m_, rf = flat_radius_m_;
  if (volume <= full_volume_m3_) {
    const double base = std::cbrt(3.0 * volume / (M_PI * slope_) + rf * rf * rf);
    cached_base_radius_m_ = base;
    cached_height_m_ = slope_ * (base - rf);
  } else {
    cached_base_radius_m_ = rc;
    cached_height_m_ = slope_ * (rc - rf) + (volume - full_volume_m3_) / (M_PI * rc * rc);
  }
}

double Pile::top_height_m(double mass_kg) {
  if (mass_kg != cached_mass_kg_) update_cache(mass_kg);
  return cached_height_m_;
}

double Pile::slope_fraction(double mass_kg) {
  if (mass_kg != cached_mass_kg_) update_cache(mass_kg);
  return std::min(1.0, cached_base_radius_m_ / container_radius_m_);
}

double Pile::fall_height_m(double mass_kg) {
  const double top = std::max(0.0, top_height_m(mass_kg) - dent_m_);
  return std::max(kMinimumFallM, orifice_to_floor_m_ - top);
}

void Pile::update_dent(double landing_fraction, double dt) {
  ++dent_steps_;
  if (dt != cached_dt_) {
    cached_dt_ = dt;
    cached_dent_share_ = -std::expm1(-dt / dent_settle_s_);
  }
  const double target = dent_depth_m_ * std::clamp(landing_fraction, 0.0, 1.0);
  dent_m_ += (target - dent_m_) * cached_dent_share_;
}

}  // namespace dynweigh::sim
