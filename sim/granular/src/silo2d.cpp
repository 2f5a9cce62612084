#include "dynweigh/granular/silo2d.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "dynweigh/granular/random.hpp"

namespace dynweigh::granular {

namespace {
const double kPi = std::acos(-1.0);

double least_squares_slope(const std::vector<double>& t, const std::vector<double>& v, double& intercept) {
  const double n = static_cast<double>(t.size());
  double mt = 0, mv = 0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    mt += t[i];
    mv += v[i];
  }
  mt /= n;
  mv /= n;
  double stv = 0, stt = 0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    stv += (t[i] - mt) * (v[i] - mv);
    stt += (t[i] - mt) * (t[i] - mt);
  }
  const double slope = stt > 0 ? stv / stt : 0.0;
  intercept = mv - slope * mt;
  return slope;
}
}  // namespace

Dem2dWorld make_silo2d(const Silo2dConfig& c) {
  if (c.moving_discs < 0 || !(c.width > 2)) throw std::invalid_argument("bad silo configuration");
  Dem2dSettings s;
  s.contact = c.contact;
  s.time_step_s = c.time_step;
  s.gravity_x = 0;
  s.gravity_y = -c.gravity;
  s.skin = c.skin;
  s.domain_min_x = -1.0;
  s.domain_max_x = c.width + 1.0;
  const double bottom = c.container_drop > 0 ? -c.container_drop - 1.0 : c.box_bottom;
  s.domain_min_y = bottom;
  s.domain_max_y = c.box_top;
  if (c.container_drop <= 0) s.remove_below_y = c.box_bottom;
  const int wall_discs = static_cast<int>(std::floor(c.width)) + 1;
  Dem2dWorld world(s, static_cast<std::size_t>(c.moving_discs + wall_discs));
  // Bottom: fixed discs; they enter the effective mass of a contact with their own mass, as the
  // peer's unintegrated wall atoms do.
  for (int k = 0; k < wall_discs; ++k) {
    DiscSpec d;
    d.x = k;
    d.y = 0.0;
    d.radius = c.wall_disc_diameter / 2;
    d.mass = c.density * kPi * d.radius * d.radius;
    d.fixed = true;
    world.add_disc(d);
  }
  // Side walls: the peer's xplane walls, tall enough to reach below the orifice.
  world.add_wall(WallSegment{0.0, bottom, 0.0, c.box_top});
  world.add_wall(WallSegment{c.width, bottom, c.width, c.box_top});
  if (c.container_drop > 0) world.add_wall(WallSegment{0.0, -c.container_drop, c.width, -c.container_drop});
  Random random(c.seed);
  const double first = c.lattice_spacing / 2;  // lattice origin 0.5 0.5 in lattice units
  int placed = 0;
  for (int row = 0; placed < c.moving_discs; ++row) {
    const double y = first + row * c.lattice_spacing;
    if (y < c.fill_min_y) continue;
    if (y > c.box_top - 1) break;
    for (int col = 0; placed < c.moving_discs; ++col) {
      const double x = first + col * c.lattice_spacing;
      if (x > c.fill_max_x) break;
      if (x < c.fill_min_x) continue;
      DiscSpec d;
      d.x = x;
      d.y = y;
      d.radius = random.uniform(c.diameter_min, c.diameter_max) / 2;
      d.mass = c.density * kPi * d.radius * d.radius;
      d.inertia_factor = c.inertia_factor;
      world.add_disc(d);
      ++placed;
    }
  }
  return world;
}

std::size_t open_silo2d_orifice(Dem2dWorld& world, const Silo2dConfig& c, int discs) {
  // Peer: c0 = W/2 - floor(n/2), c1 = c0 + n - 1, delete bottom atoms with x in [c0-0.1, c1+0.1].
  const double c0 = std::floor(c.width / 2) - std::floor(discs / 2.0);
  const double c1 = c0 + discs - 1;
  return world.remove_discs_in_box(c0 - 0.1, c1 + 0.1, -0.5, 0.5, true);
}

DischargeResult measure_silo2d_discharge(Dem2dWorld& world, std::size_t stop_below, std::int64_t max_steps,
                                         std::int64_t sample_every, double skip_fraction) {
  DischargeResult result;
  const std::size_t start_count = world.count_moving_above(0.5);
  result.samples.push_back({world.time(), start_count});
  std::int64_t done = 0;
  while (done < max_steps) {
    for (std::int64_t s = 0; s < sample_every && done < max_steps; ++s, ++done) {
      world.step();
      result.particle_steps += static_cast<double>(world.size());
    }
    const std::size_t above = world.count_moving_above(0.5);
    result.samples.push_back({world.time(), above});
    if (above < stop_below) break;
  }
  result.steps = done;
  fit_discharge_rates(result, skip_fraction);
  return result;
}

void fit_discharge_rates(DischargeResult& result, double skip_fraction) {
  if (result.samples.empty()) return;
  const double start_count = static_cast<double>(result.samples.front().above);
  const double total = start_count - static_cast<double>(result.samples.back().above);
  std::vector<double> t, v;
  for (const auto& sample : result.samples) {
    if (start_count - static_cast<double>(sample.above) >= skip_fraction * total) {
      t.push_back(sample.time);
      v.push_back(static_cast<double>(sample.above));
    }
  }
  if (t.size() < 4) return;
  double intercept;
  result.rate = -least_squares_slope(t, v, intercept);
  const std::size_t half = t.size() / 2;
  std::vector<double> t1(t.begin(), t.begin() + static_cast<std::ptrdiff_t>(half + 1));
  std::vector<double> v1(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(half + 1));
  std::vector<double> t2(t.begin() + static_cast<std::ptrdiff_t>(half), t.end());
  std::vector<double> v2(v.begin() + static_cast<std::ptrdiff_t>(half), v.end());
  result.rate_first_half = -least_squares_slope(t1, v1, intercept);
  result.rate_second_half = -least_squares_slope(t2, v2, intercept);
}

BeverlooFit fit_beverloo_2d(const std::vector<double>& orifice, const std::vector<double>& rate, double grain_diameter) {
  BeverlooFit fit;
  if (orifice.size() != rate.size() || orifice.size() < 2) return fit;
  std::vector<double> linearised(rate.size());
  for (std::size_t i = 0; i < rate.size(); ++i) linearised[i] = std::cbrt(rate[i] * rate[i]);
  double intercept;
  const double slope = least_squares_slope(orifice, linearised, intercept);
  if (slope <= 0) return fit;
  fit.c = std::pow(slope, 1.5);
  fit.k = -intercept / slope / grain_diameter;
  for (std::size_t i = 0; i < rate.size(); ++i) {
    const double model = fit.c * std::pow(std::max(0.0, orifice[i] - fit.k * grain_diameter), 1.5);
    fit.worst_relative_residual = std::max(fit.worst_relative_residual, std::fabs(model - rate[i]) / rate[i]);
  }
  return fit;
}

}  // namespace dynweigh::granular
