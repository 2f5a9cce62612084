#include "dynweigh/granular/outflow_profile.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace dynweigh::granular {

OutflowProfile make_outflow_profile(double x_min, double x_max, double y_level, double band, int bins) {
  if (!(x_max > x_min) || bins < 1 || !(band > 0)) throw std::invalid_argument("bad outflow profile");
  OutflowProfile p;
  p.x_min = x_min;
  p.x_max = x_max;
  p.y_level = y_level;
  p.band = band;
  p.speed_sum.assign(static_cast<std::size_t>(bins), 0.0);
  p.disc_count.assign(static_cast<std::size_t>(bins), 0.0);
  return p;
}

OutflowProfile make_silo2d_outflow_profile(double silo_width, int orifice, int bins) {
  // As open_silo2d_orifice: bottom discs (diameter 1) c0 .. c0 + n - 1 are removed, so the gap
  // runs from the edge of disc c0 - 1 to the edge of disc c0 + n.
  const double c0 = std::floor(silo_width / 2) - std::floor(orifice / 2.0);
  return make_outflow_profile(c0 - 0.5, c0 + orifice - 0.5, 0.0, 0.5, bins);
}

void sample_outflow(OutflowProfile& p, const Dem2dWorld& world) {
  const std::size_t bins = p.speed_sum.size();
  const double per_width = static_cast<double>(bins) / (p.x_max - p.x_min);
  for (std::size_t i = 0; i < world.size(); ++i) {
    if (world.fixed(i)) continue;
    const double x = world.x(i);
    if (std::fabs(world.y(i) - p.y_level) >= p.band || x < p.x_min || x >= p.x_max) continue;
    const auto bin = std::min(bins - 1, static_cast<std::size_t>((x - p.x_min) * per_width));
    p.speed_sum[bin] -= world.vy(i);
    p.disc_count[bin] += 1.0;
  }
  ++p.samples;
}

OutflowSummary summarize_outflow(const OutflowProfile& p) {
  OutflowSummary s;
  if (p.speed_sum.empty()) return s;
  for (std::size_t b = 0; b < p.speed_sum.size(); ++b) {
    const double mean = p.disc_count[b] > 0 ? p.speed_sum[b] / p.disc_count[b] : 0.0;
    s.mean_speed += mean;
    s.peak_speed = std::max(s.peak_speed, mean);
    s.sampled_discs += p.disc_count[b];
  }
  s.mean_speed /= static_cast<double>(p.speed_sum.size());
  s.alpha = s.peak_speed > 0 ? s.mean_speed / s.peak_speed : 0.0;
  return s;
}

}  // namespace dynweigh::granular
