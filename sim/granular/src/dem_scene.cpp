#include "dynweigh/granular/dem_scene.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "dynweigh/granular/dem2d_world.hpp"
#include "dynweigh/granular/random.hpp"
#include "dynweigh/granular/thread_cpu_time.hpp"
#include "dynweigh/model/bore_area.hpp"

namespace dynweigh::granular {

namespace {

const double kPi = std::acos(-1.0);

// The derived sizes of a scene's DEM, SI.
struct DemSceneUnits {
  double d = 0;             // mean disc diameter
  double slot_depth = 0;    // pi D / 4
  double areal_density = 0; // disc density times slot depth, kg/m^2
  double time_unit = 0;     // sqrt(d / g)
  double disc_mass(double diameter) const { return areal_density * kPi * 0.25 * diameter * diameter; }
};

DemSceneUnits units_of(const DemSceneConfig& c) {
  DemSceneUnits u;
  u.d = c.bore_m / c.discs_across_orifice;
  u.slot_depth = kPi * c.bore_m / 4.0;
  u.areal_density = c.bulk_density / c.packing_fraction_2d * u.slot_depth;
  u.time_unit = std::sqrt(u.d / c.gravity);
  return u;
}

// The peer's contact numbers are per unit of d, disc mass (density 1 per area) and sqrt(d/g).
ContactParameters contact_in_si(const DemSceneConfig& c, const DemSceneUnits& u) {
  const double stiffness_unit = u.areal_density * u.d * c.gravity;  // (mass unit) g / d
  ContactParameters si = c.reduced_contact;
  si.normal_stiffness *= stiffness_unit;
  si.tangential_stiffness *= stiffness_unit;
  si.normal_damping /= u.time_unit;
  si.tangential_damping /= u.time_unit;
  return si;
}

// Stroke of the gate at time t after the open command (close command at close_s).
double gate_stroke(const DemSceneConfig& c, double t) {
  const auto opening = [&](double time) {
    if (time < c.valve_dead_time_s) return 0.0;
    if (c.valve_full_stroke_s <= 0) return 1.0;
    return std::min(1.0, (time - c.valve_dead_time_s) / c.valve_full_stroke_s);
  };
  const double close_start = c.close_s + c.valve_dead_time_s;
  if (!c.with_container || t < close_start) return opening(t);
  const double at_close = opening(close_start);
  if (c.valve_full_stroke_s <= 0) return 0.0;
  return std::max(0.0, at_close - (t - close_start) / c.valve_full_stroke_s);
}

// The gate: one segment under the slot that slides toward +x, uncovering [-D/2, -D/2 + w).
WallSegment gate_at(const DemSceneConfig& c, const DemSceneUnits& u, double stroke) {
  const double open_width = c.bore_m * std::sqrt(model::open_area_fraction(stroke));
  const double left = -0.5 * c.bore_m + open_width;
  const double level = 0.5 * u.d;
  return WallSegment{left, level, left + c.bore_m + u.d, level};
}

struct Layout {
  std::size_t gate = 0;
  std::size_t container_first = 0, container_last = 0;  // wall indices, inclusive
  double bed_top = 0;
};

Dem2dWorld build_world(const DemSceneConfig& c, const DemSceneUnits& u, std::uint64_t seed, Layout& layout) {
  const double silo_half = 0.5 * c.silo_width_bores * c.bore_m;
  const double container_half = 0.5 * c.container_width_m;
  const double spacing = 1.12 * u.d;  // the peer's fill lattice
  const double first_x = -silo_half + 0.75 * u.d;
  const int per_row = std::max(1, static_cast<int>(std::floor((2 * silo_half - 1.5 * u.d) / spacing)) + 1);
  const int rows = (c.fill_discs + per_row - 1) / per_row;
  const double top = 1.5 * u.d + rows * spacing + 2 * u.d;
  layout.bed_top = top;

  Dem2dSettings s;
  s.contact = contact_in_si(c, u);
  s.time_step_s = c.reduced_time_step * u.time_unit;
  s.gravity_y = -c.gravity;
  s.skin = 0.3 * u.d;
  const double half = std::max(silo_half, container_half) + 2 * u.d;
  s.domain_min_x = -half;
  s.domain_max_x = half;
  const double floor_y = c.with_container ? -c.fall_height_m : -3 * u.d;
  s.domain_min_y = floor_y - 6 * u.d;
  s.domain_max_y = top;
  s.remove_below_y = c.with_container ? floor_y - 5 * u.d : floor_y;

  // Bottom discs of diameter d either side of the slot, fixed (the peer's rough bottom).
  const int side_discs = static_cast<int>(std::floor((silo_half - 0.5 * c.bore_m) / u.d));
  Dem2dWorld world(s, static_cast<std::size_t>(c.fill_discs + 2 * side_discs + 2));
  for (int k = 0; k < side_discs; ++k) {
    for (const double sign : {-1.0, 1.0}) {
      DiscSpec wall_disc;
      wall_disc.x = sign * (0.5 * c.bore_m + (k + 0.5) * u.d);
      wall_disc.y = 0;
      wall_disc.radius = 0.5 * u.d;
      wall_disc.mass = u.disc_mass(u.d);
      wall_disc.fixed = true;
      world.add_disc(wall_disc);
    }
  }
  world.add_wall(WallSegment{-silo_half, -u.d, -silo_half, top});
  world.add_wall(WallSegment{silo_half, -u.d, silo_half, top});
  layout.gate = world.add_wall(gate_at(c, u, 0.0));
  if (c.with_container) {
    const double wall_top = floor_y + c.container_width_m;
    layout.container_first = world.add_wall(WallSegment{-container_half, floor_y, container_half, floor_y});
    world.add_wall(WallSegment{-container_half, floor_y, -container_half, wall_top});
    layout.container_last = world.add_wall(WallSegment{container_half, floor_y, container_half, wall_top});
  }
  Random random(seed);
  for (int placed = 0; placed < c.fill_discs; ++placed) {
    DiscSpec disc;
    disc.x = first_x + (placed % per_row) * spacing;
    disc.y = 1.5 * u.d + (placed / per_row) * spacing;
    const double diameter = u.d * random.uniform(0.9, 1.1);
    disc.radius = 0.5 * diameter;
    disc.mass = u.disc_mass(diameter);
    disc.inertia_factor = 0.5;  // discs
    world.add_disc(disc);
  }
  return world;
}

double moving_mass(const Dem2dWorld& world) {
  double mass = 0;
  for (std::size_t i = 0; i < world.size(); ++i) {
    if (!world.fixed(i)) mass += world.mass(i);
  }
  return mass;
}

double mass_below(const Dem2dWorld& world, double y) {
  double mass = 0;
  for (std::size_t i = 0; i < world.size(); ++i) {
    if (!world.fixed(i) && world.y(i) < y) mass += world.mass(i);
  }
  return mass;
}

// Settles the closed silo until the discs are at rest (mean kinetic energy per disc below
// 1e-4 m g d) or the time is up. Returns the simulated time.
double settle(Dem2dWorld& world, const DemSceneConfig& c, const DemSceneUnits& u, double& particle_steps,
              const std::function<void(double)>& progress) {
  const double rest = 1e-4 * u.disc_mass(u.d) * c.gravity * u.d * static_cast<double>(world.moving_count());
  const auto max_steps = static_cast<std::int64_t>(c.settle_reduced_time_max / c.reduced_time_step);
  const auto min_steps = static_cast<std::int64_t>(5.0 / c.reduced_time_step);
  constexpr std::int64_t kCheckEvery = 500;
  std::int64_t done = 0;
  while (done < max_steps) {
    world.run(kCheckEvery);
    done += kCheckEvery;
    particle_steps += static_cast<double>(world.size()) * kCheckEvery;
    if (progress) progress(0.2 * static_cast<double>(done) / static_cast<double>(max_steps));
    if (done >= min_steps && world.kinetic_energy() < rest) break;
  }
  return world.time();
}

double bed_bulk_density(const Dem2dWorld& world, const DemSceneConfig& c, const DemSceneUnits& u) {
  double top = 0;
  for (std::size_t i = 0; i < world.size(); ++i) {
    if (!world.fixed(i)) top = std::max(top, world.y(i));
  }
  const double half = 0.5 * c.silo_width_bores * c.bore_m - 2 * u.d;
  const double low = 3 * u.d, high = top - 3 * u.d;
  if (!(high > low) || !(half > 0)) return 0;
  double mass = 0;
  for (std::size_t i = 0; i < world.size(); ++i) {
    if (!world.fixed(i) && std::fabs(world.x(i)) < half && world.y(i) > low && world.y(i) < high) mass += world.mass(i);
  }
  return mass / (2 * half * (high - low) * u.slot_depth);
}

}  // namespace

DemSceneRun run_dem_scene(const DemSceneConfig& c, std::uint64_t seed, const std::function<void(double)>& progress) {
  if (!(c.bore_m > 0) || !(c.fall_height_m > 0) || !(c.discs_across_orifice >= 2) || c.fill_discs < 1 ||
      !(c.silo_width_bores > 1) || !(c.sample_period_s > 0) || !(c.close_s > 0)) {
    throw std::invalid_argument("bad DEM scene configuration");
  }
  const DemSceneUnits u = units_of(c);
  Layout layout;
  Dem2dWorld world = build_world(c, u, seed, layout);
  DemSceneRun run;
  run.grain_diameter_m = u.d;
  run.disc_mass_kg = u.disc_mass(u.d);
  run.slot_depth_m = u.slot_depth;
  run.discs = static_cast<std::int64_t>(world.moving_count());
  const double cpu_start = thread_cpu_seconds();
  run.settle_s = settle(world, c, u, run.particle_steps, progress);
  run.bed_bulk_density = bed_bulk_density(world, c, u);

  const double dt = world.settings().time_step_s;
  const double start = world.time();
  const double initial_mass = moving_mass(world);
  const double last_landing = c.close_s + c.valve_dead_time_s + c.valve_full_stroke_s +
                              std::sqrt(2.0 * c.fall_height_m / c.gravity);
  const double end = c.with_container ? last_landing + c.settle_s : c.close_s;
  const auto steps_per_sample = std::max<std::int64_t>(1, std::llround(c.sample_period_s / dt));
  const auto total_steps = static_cast<std::int64_t>(std::ceil(end / dt));
  const double released_below = 0.0;  // past the bottom discs' centres
  // The slot's speed profile while the gate is fully open and the flow has settled.
  const double profile_from = c.valve_dead_time_s + c.valve_full_stroke_s + 0.1;
  const double profile_to = c.with_container ? c.close_s + c.valve_dead_time_s : c.close_s;
  OutflowProfile profile = make_outflow_profile(-0.5 * c.bore_m, 0.5 * c.bore_m, 0.0, 0.5 * u.d, c.profile_bins);
  constexpr std::int64_t kProfileEvery = 20;

  double force_sum = 0;
  double applied_stroke = 0;
  for (std::int64_t s = 1; s <= total_steps; ++s) {
    const double t = world.time() - start;
    const double stroke = gate_stroke(c, t);
    if (stroke != applied_stroke) {
      world.move_wall(layout.gate, gate_at(c, u, stroke));
      applied_stroke = stroke;
    }
    world.step();
    run.particle_steps += static_cast<double>(world.size());
    if (c.with_container) {
      for (std::size_t w = layout.container_first; w <= layout.container_last; ++w) force_sum -= world.wall_force(w).y;
    }
    const double now = world.time() - start;
    if (s % kProfileEvery == 0 && now > profile_from && now < profile_to) sample_outflow(profile, world);
    if (s % steps_per_sample == 0) {
      run.time_s.push_back(now);
      run.force_n.push_back(force_sum / static_cast<double>(steps_per_sample));
      const double lost = initial_mass - moving_mass(world);
      run.released_kg.push_back(mass_below(world, released_below) + lost);
      force_sum = 0;
      if (progress && s % (64 * steps_per_sample) == 0) {
        progress(0.2 + 0.8 * static_cast<double>(s) / static_cast<double>(total_steps));
      }
    }
  }
  run.steps = world.steps();
  run.outflow = summarize_outflow(profile);
  run.lost_kg = c.with_container ? initial_mass - moving_mass(world) : 0.0;
  run.released_total_kg = run.released_kg.empty() ? 0.0 : run.released_kg.back();
  run.cpu_seconds = thread_cpu_seconds() - cpu_start;
  return run;
}

double steady_discharge_kg_s(const DemSceneRun& run, double from_s, double to_s) {
  double n = 0, mt = 0, mm = 0;
  for (std::size_t k = 0; k < run.time_s.size(); ++k) {
    if (run.time_s[k] < from_s || run.time_s[k] > to_s) continue;
    n += 1;
    mt += run.time_s[k];
    mm += run.released_kg[k];
  }
  if (n < 3) return 0;
  mt /= n;
  mm /= n;
  double stm = 0, stt = 0;
  for (std::size_t k = 0; k < run.time_s.size(); ++k) {
    if (run.time_s[k] < from_s || run.time_s[k] > to_s) continue;
    stm += (run.time_s[k] - mt) * (run.released_kg[k] - mm);
    stt += (run.time_s[k] - mt) * (run.time_s[k] - mt);
  }
  return stt > 0 ? stm / stt : 0;
}

}  // namespace dynweigh::granular
