#include "dynweigh/sim/plant.hpp"

#include <algorithm>
#include <cmath>

namespace dynweigh::sim {
namespace {

std::uint64_t stream_seed(std::uint64_t seed, std::uint64_t stream) {
  return seed * 0x9E3779B97F4A7C15ULL + stream;  // one independent stream per component
}

// Parcels the column must hold: one per sub-interval of a step (the step, split at fluctuation
// knots and valve breakpoints) for the longest fall the scene allows (v0 = 0 onto the floor).
std::size_t column_capacity(const Scene& scene, const SiloParameters& silo, double fall_height_m) {
  const double longest_fall_s = std::sqrt(2.0 * fall_height_m / scene.g) + 0.1;
  const double steps = std::ceil(longest_fall_s / scene.internal_step_s);
  const double knot_s = silo.fluctuation_correlation_s / 30.0;
  const double per_step = 3.0 + (silo.fluctuation_rms > 0.0 ? std::ceil(scene.internal_step_s / knot_s) : 0.0);
  return static_cast<std::size_t>(std::min(steps * per_step + 64.0, 4e6));
}

double moving_load_kg(const Scene& scene, double static_kg) {
  // Hourglass: everything stands on the scale and moves with it, whatever is where.
  return scene.hourglass.enabled ? scene.hourglass.silo_tare_kg + scene.silo.fill_kg : static_kg;
}

}  // namespace

Plant::ExtraStream::ExtraStream(const IngredientParameters& p, double g, std::size_t capacity, std::uint64_t seed)
    : parameters(p), valve(p.valve, stream_seed(seed, 1)), silo(p.silo, g, stream_seed(seed, 2)), column(g, capacity) {}

Plant::Plant(const Scene& scene, std::uint64_t seed)
    : scene_(scene),
      components_(components_of(scene)),
      dt_(scene.internal_step_s),
      reference_weight_n_((scene.platform.container_kg + moving_load_kg(scene, 0.0)) * scene.g),
      valve_(scene.valve, stream_seed(seed, 1)),
      gate_(scene.gate),
      silo_(scene.silo, scene.g, stream_seed(seed, 2)),
      column_(scene.g, column_capacity(scene, scene.silo, scene.column.fall_height_m)),
      load_cell_(scene.load_cell, scene.g, stream_seed(seed, 3),
                 components_.has(Component::creep) ? &scene.creep : nullptr),
      rigid_support_force_n_(reference_weight_n_) {
  if (components_.has(Component::pile)) {
    pile_.emplace(scene.column, components_.has(Component::pile_top) ? &scene.pile_top : nullptr,
                  scene.silo.bulk_density);
  }
  if (components_.has(Component::impact_relaxation)) impact_.emplace(scene.impact.relaxation_s);
  if (components_.has(Component::avalanche)) avalanches_.emplace(scene.avalanche);
  if (components_.has(Component::platform)) {
    platform_.emplace(scene.platform, scene.g);
    // Start at rest under what stands on it (the empty container, or the whole hourglass).
    platform_->rest_under(reference_weight_n_);
  }
  const std::size_t ingredients = std::min(scene.ingredients.size(), kMaxIngredients);
  extra_.reserve(ingredients > 1 ? ingredients - 1 : 0);
  for (std::size_t i = 1; i < ingredients; ++i) {
    const IngredientParameters& p = scene.ingredients[i];
    // Each ingredient draws from its own random streams (ingredient 0 keeps the plant's).
    extra_.emplace_back(p, scene.g, column_capacity(scene, p.silo, p.fall_height_m), stream_seed(seed, 100 + i));
  }
  truth_.silo_kg = silo_.remaining_kg();
  truth_.ingredients[0].silo_kg = silo_.remaining_kg();
  for (std::size_t i = 0; i < extra_.size(); ++i) {
    truth_.silo_kg += extra_[i].silo.remaining_kg();
    truth_.ingredients[i + 1].silo_kg = extra_[i].silo.remaining_kg();
  }
  truth_.fall_height_m = fall_height_m();
  truth_.force_n = support_force_n() - reference_weight_n_;
}

bool Plant::command_ingredient_valve(std::size_t ingredient, ValveCommand command, double delay_s) {
  if (ingredient == 0) {
    command_valve(command, delay_s);
    return true;
  }
  if (ingredient > extra_.size()) return false;
  ExtraStream& stream = extra_[ingredient - 1];
  if (command == stream.last_command) return true;
  stream.last_command = command;
  stream.valve.command(command, truth_.time_s + delay_s);
  return true;
}

ValvePosition Plant::ingredient_valve_feedback(std::size_t ingredient) const {
  if (ingredient == 0) return valve_.feedback();
  if (ingredient > extra_.size()) return ValvePosition::closed;
  return extra_[ingredient - 1].valve.feedback();
}

double Plant::empty_counts() const { return load_cell_.ideal_counts(reference_weight_n_); }

std::uint64_t Plant::component_steps(Component component) const {
  switch (component) {
    case Component::silo: return silo_.steps();
    case Component::valve: return valve_.steps();
    case Component::column: return column_.steps();
    case Component::pile: return pile_ ? pile_->steps() : 0;
    case Component::pile_top: return pile_ && components_.has(Component::pile_top) ? pile_->dent_steps() : 0;
    case Component::impact_relaxation: return impact_ ? impact_->steps() : 0;
    case Component::avalanche: return avalanches_ ? avalanches_->steps() : 0;
    case Component::platform: return platform_ ? platform_->steps() : 0;
    case Component::load_cell: return load_cell_.conversions();
    case Component::creep: return load_cell_.creep_steps();
    case Component::hourglass: return components_.has(Component::hourglass) ? steps_ : 0;
  }
  return 0;
}

void Plant::command_valve(ValveCommand command, double delay_s) {
  if (command == last_command_) return;
  last_command_ = command;
  valve_.command(command, truth_.time_s + delay_s);
}

void Plant::add_to_silo(double kg) {
  if (!(kg > 0.0)) return;
  silo_.add(kg);
  truth_.refilled_kg += kg;
  truth_.ingredients[0].refilled_kg += kg;
  truth_.silo_kg = silo_.remaining_kg();
}

// The level switch starts the feeder below refill_below_kg; it runs until the silo is back at
// its fill level. A scene without a level (0) is only refilled by a command.
void Plant::refill_step() {
  const SiloParameters& silo = scene_.silo;
  if (silo.refill_below_kg > 0.0 && silo_.remaining_kg() < silo.refill_below_kg) truth_.refilling = true;
  if (!truth_.refilling) return;
  const double room_kg = silo.fill_kg - silo_.remaining_kg();
  const double poured_kg = std::min(room_kg, silo.refill_rate_kg_s * dt_);
  if (poured_kg > 0.0) {
    silo_.add(poured_kg);
    truth_.refilled_kg += poured_kg;
    truth_.ingredients[0].refilled_kg += poured_kg;
  }
  if (poured_kg >= room_kg) truth_.refilling = false;
}

// The hopper empties through the gate at a rate proportional to its stroke, never more than it
// holds. What leaves falls clear of the scale: no reaction on the platform.
double Plant::discharge_step(double dt) {
  const double mean_stroke = gate_.advance(dt);
  truth_.gate_stroke = gate_.stroke();
  if (mean_stroke <= 0.0 || truth_.static_kg <= 0.0) return 0.0;
  const double emptied_kg = std::min(truth_.static_kg, scene_.gate.discharge_kg_s * mean_stroke * dt);
  truth_.static_kg -= emptied_kg;
  truth_.discharged_kg += emptied_kg;
  return emptied_kg;
}

double Plant::fall_height_m() {
  return pile_ ? pile_->fall_height_m(truth_.static_kg) : scene_.column.fall_height_m;
}

void Plant::advance(double seconds) {
  const auto count = static_cast<std::int64_t>(std::llround(seconds / dt_));
  for (std::int64_t i = 0; i < count; ++i) step();
}

Plant::Release Plant::release_step(Silo& silo, PneumaticValve& valve, FallingColumn& column, double begin, double end,
                                   double& own_released_kg) {
  const double dt = dt_;
  Release release;
  // The stroke is piecewise linear and the fluctuation linear between knots: integrate the
  // outflow between their breakpoints; each piece leaves as one parcel at its middle.
  for (double a = begin; a < end;) {
    double b = silo.next_breakpoint_s(a, valve.next_breakpoint_s(end));
    // A breakpoint within rounding of the step's end (a knot on the step grid) is the end.
    if (b <= a || end - b < 1e-9 * dt) b = end;
    const double stroke_a = valve.stroke();
    valve.advance_to(b);
    // An instant gate holds its stroke over the piece and jumps at its end.
    const double stroke_b = valve.instant() ? stroke_a : valve.stroke();
    const Silo::Outflow out = silo.discharge(a, stroke_a, stroke_b, b - a);
    if (out.mass_kg > 0.0) {
      const double release_s = 0.5 * (a + b);
      column.release(release_s, out.mass_kg, out.speed_m_s);
      truth_.released_kg += out.mass_kg;
      own_released_kg += out.mass_kg;
      release.weighted_kg_s += out.mass_kg * (end - release_s);
      release.momentum_n_s += out.mass_kg * out.speed_m_s;
    }
    a = b;
  }
  return release;
}

void Plant::refill_extra(ExtraStream& stream, IngredientTruth& truth) {
  const SiloParameters& silo = stream.parameters.silo;
  if (silo.refill_below_kg > 0.0 && stream.silo.remaining_kg() < silo.refill_below_kg) stream.refilling = true;
  if (!stream.refilling) return;
  const double room_kg = silo.fill_kg - stream.silo.remaining_kg();
  const double poured_kg = std::min(room_kg, silo.refill_rate_kg_s * dt_);
  if (poured_kg > 0.0) {
    stream.silo.add(poured_kg);
    truth_.refilled_kg += poured_kg;
    truth.refilled_kg += poured_kg;
  }
  if (poured_kg >= room_kg) stream.refilling = false;
}

void Plant::step() {
  const double dt = dt_;
  const double begin = double(steps_) * dt;
  const double end = double(steps_ + 1) * dt;
  const double silo_before_kg = silo_.remaining_kg();
  const Release release = release_step(silo_, valve_, column_, begin, end, truth_.ingredients[0].released_kg);
  const double released_weighted_kg_s = release.weighted_kg_s;
  const double release_momentum_n_s = release.momentum_n_s;
  for (std::size_t i = 0; i < extra_.size(); ++i) {
    ExtraStream& stream = extra_[i];
    // Not on the scale (the hourglass has no ingredients): what they release matters only when it lands.
    release_step(stream.silo, stream.valve, stream.column, begin, end, truth_.ingredients[i + 1].released_kg);
    refill_extra(stream, truth_.ingredients[i + 1]);
  }
  refill_step();

  const double fall = fall_height_m();
  FallingColumn::Landing landing = column_.land(begin, end, fall);
  for (ExtraStream& stream : extra_) {
    // Its orifice stands higher or lower than ingredient 0's by the difference of their heights.
    const double own_fall = std::max(fall + stream.parameters.fall_height_m - scene_.column.fall_height_m, 1e-3);
    const FallingColumn::Landing own = stream.column.land(begin, end, own_fall);
    landing.mass_kg += own.mass_kg;
    landing.momentum_n_s += own.momentum_n_s;
    landing.resting_kg_s += own.resting_kg_s;
    landing.resting_momentum_n_s2 += own.resting_momentum_n_s2;
  }
  const double static_before_kg = truth_.static_kg;
  truth_.static_kg += landing.mass_kg;
  double mean_static_kg = static_before_kg + landing.resting_kg_s / dt;
  if (const double emptied_kg = discharge_step(dt); emptied_kg > 0.0) {
    mean_static_kg -= 0.5 * emptied_kg;  // it leaves evenly over the step
  }

  double impact = impact_ ? impact_->force_over_step(landing.momentum_n_s, dt, landing.resting_momentum_n_s2) : landing.momentum_n_s / dt;
  if (avalanches_) impact += avalanches_->step(landing.mass_kg, pile_->slope_fraction(truth_.static_kg), begin, end);
  if (pile_ && components_.has(Component::pile_top)) {
    const double full_rate = silo_.full_open_rate_kg_s();
    pile_->update_dent(full_rate > 0.0 ? landing.mass_kg / (dt * full_rate) : 0.0, dt);
  }

  // Mean force over the step on what the load cell carries.
  double external_n = (scene_.platform.container_kg + test_weight_kg_ + mean_static_kg) * scene_.g + impact;
  if (components_.has(Component::hourglass)) {
    // The silo stands on the scale too: its content weighs until it leaves, and the bed pushes
    // each parcel to v0 on the way out (the reaction lightens the silo by mdot v0).
    const double mean_silo_kg = silo_before_kg - released_weighted_kg_s / dt;
    external_n += (scene_.hourglass.silo_tare_kg + mean_silo_kg) * scene_.g - release_momentum_n_s / dt;
  }
  double support_impulse_n_s = external_n * dt;
  if (platform_) {
    platform_->step(external_n, moving_load_kg(scene_, truth_.static_kg) + test_weight_kg_, dt);
    support_impulse_n_s = platform_->last_support_impulse_n_s();
  } else {
    // A rigid scale reads the force of the instant the step ends: the weights as they are then
    // (not their mean over the step, half a step of ramp behind), the fluxes at their step mean.
    rigid_support_force_n_ = external_n + (truth_.static_kg - mean_static_kg) * scene_.g;
    if (components_.has(Component::hourglass)) {
      rigid_support_force_n_ += (silo_.remaining_kg() - (silo_before_kg - released_weighted_kg_s / dt)) * scene_.g;
    }
  }

  ++steps_;
  truth_.time_s = end;
  truth_.in_flight_kg = column_.in_flight_kg();
  truth_.silo_kg = silo_.remaining_kg();
  truth_.ingredients[0].in_flight_kg = column_.in_flight_kg();
  truth_.ingredients[0].silo_kg = silo_.remaining_kg();
  truth_.ingredients[0].stroke = valve_.stroke();
  for (std::size_t i = 0; i < extra_.size(); ++i) {
    IngredientTruth& own = truth_.ingredients[i + 1];
    own.in_flight_kg = extra_[i].column.in_flight_kg();
    own.silo_kg = extra_[i].silo.remaining_kg();
    own.stroke = extra_[i].valve.stroke();
    truth_.in_flight_kg += own.in_flight_kg;
    truth_.silo_kg += own.silo_kg;
  }
  truth_.force_n = support_force_n() - reference_weight_n_;
  truth_.force_impulse_n_s += support_impulse_n_s - reference_weight_n_ * dt;
  truth_.impact_force_n = impact;
  truth_.stroke = valve_.stroke();
  truth_.fall_height_m = fall;
  if (avalanches_) truth_.avalanches = avalanches_->avalanches();
}

}  // namespace dynweigh::sim
