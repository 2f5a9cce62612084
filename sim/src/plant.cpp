#include "dynweigh/sim/plant.hpp"

#include <cmath>

namespace dynweigh::sim {
namespace {

std::uint64_t stream_seed(std::uint64_t seed, std::uint64_t stream) {
  return seed * 0x9E3779B97F4A7C15ULL + stream;  // one independent stream per component
}

double longest_fall_s(const Scene& scene) {
  return std::sqrt(2.0 * scene.column.fall_height_m / scene.g) + 0.1;
}

}  // namespace

Plant::Plant(const Scene& scene, std::uint64_t seed)
    : scene_(scene),
      pile_{scene.column.container_diameter_m, scene.column.repose_angle_deg * M_PI / 180.0,
            scene.silo.bulk_density},
      valve_(scene.valve, stream_seed(seed, 1)),
      silo_(scene.silo, scene.g, stream_seed(seed, 2)),
      column_(scene.g, longest_fall_s(scene), scene.internal_step_s),
      impact_(scene.impact.relaxation_s),
      platform_(scene.platform, scene.g),
      load_cell_(scene.load_cell, scene.g, stream_seed(seed, 3)) {
  truth_.fall_height_m = current_fall_height_m();
}

double Plant::empty_counts() const {
  return load_cell_.ideal_counts(scene_.platform.container_kg * scene_.g);
}

void Plant::command_valve(ValveCommand command, double delay_s) {
  if (command == last_command_) return;
  last_command_ = command;
  valve_.command(command, truth_.time_s + delay_s);
}

double Plant::current_fall_height_m() const {
  if (!scene_.column.pile_grows) return scene_.column.fall_height_m;
  return model::fall_height_to_pile_m(pile_, scene_.column.fall_height_m, truth_.static_kg);
}

void Plant::advance(double seconds) {
  const double dt = scene_.internal_step_s;
  const auto count = static_cast<std::uint64_t>(std::llround(seconds / dt));
  for (std::uint64_t i = 0; i < count; ++i) step(dt);
}

void Plant::step(double dt) {
  const double begin = double(steps_) * dt;
  const double end = double(steps_ + 1) * dt;
  // The stroke is piecewise linear: integrate the outflow between its breakpoints.
  for (double a = begin; a < end;) {
    double b = valve_.next_breakpoint_s(end);
    if (b <= a) b = end;
    const double stroke_a = valve_.stroke();
    valve_.advance_to(b);
    const Silo::Outflow out = silo_.discharge(stroke_a, valve_.stroke(), b - a);
    column_.release(0.5 * (a + b), out.mass_kg, out.speed_m_s);
    truth_.released_kg += out.mass_kg;
    a = b;
  }
  const double fall = current_fall_height_m();
  const FallingColumn::Landing landing = column_.land(end, fall);
  truth_.static_kg += landing.mass_kg;
  truth_.impact_force_n = impact_.force_over_step(landing.momentum_n_s, dt);
  const double container = platform_.container_kg();
  platform_.step((container + truth_.static_kg) * scene_.g + truth_.impact_force_n, truth_.static_kg, dt);

  ++steps_;
  truth_.time_s = end;
  truth_.in_flight_kg = column_.in_flight_kg();
  truth_.force_n = platform_.support_force_n() - container * scene_.g;
  truth_.stroke = valve_.stroke();
  truth_.fall_height_m = fall;
}

}  // namespace dynweigh::sim
