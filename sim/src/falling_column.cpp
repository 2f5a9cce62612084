#include "dynweigh/sim/falling_column.hpp"

#include <algorithm>
#include <cmath>

#include "dynweigh/model/ideal_model.hpp"

namespace dynweigh::sim {

FallingColumn::FallingColumn(double g, std::size_t capacity) : g_(g), ring_(std::max<std::size_t>(capacity, 2)) {}

void FallingColumn::release(double time_s, double mass_kg, double speed_m_s) {
  if (mass_kg <= 0.0) return;
  in_flight_kg_ += mass_kg;
  if (count_ == ring_.size()) {
    // Only a fall longer than the scene declared gets here: keep the mass, merge into the newest.
    ring_[(head_ + count_ - 1) % ring_.size()].mass_kg += mass_kg;
    return;
  }
  ring_[(head_ + count_) % ring_.size()] = {time_s, mass_kg, speed_m_s};
  ++count_;
}

FallingColumn::Landing FallingColumn::land(double step_begin_s, double step_end_s, double fall_height_m) {
  ++steps_;
  Landing landing;
  const double dt = step_end_s - step_begin_s;
  while (count_ > 0) {
    const Parcel& parcel = ring_[head_];
    const double elapsed = step_end_s - parcel.release_s;
    const double fallen = parcel.speed_m_s * elapsed + 0.5 * g_ * elapsed * elapsed;
    if (fallen < fall_height_m) break;
    // Landing instant for the present height; if the pile rose past the parcel during an earlier
    // step, it lands at this step's start with the speed it actually had then.
    double airborne_s = model::fall_time(parcel.speed_m_s, g_, fall_height_m);
    airborne_s = std::clamp(airborne_s, step_begin_s - parcel.release_s, elapsed);
    airborne_s = std::max(airborne_s, 0.0);
    const double landed_s = parcel.release_s + airborne_s;
    landing.mass_kg += parcel.mass_kg;
    const double momentum = parcel.mass_kg * (parcel.speed_m_s + g_ * airborne_s);
    const double resting_s = std::clamp(step_end_s - landed_s, 0.0, dt);
    landing.momentum_n_s += momentum;
    landing.resting_kg_s += parcel.mass_kg * resting_s;
    landing.resting_momentum_n_s2 += momentum * resting_s;
    in_flight_kg_ -= parcel.mass_kg;
    head_ = head_ + 1 == ring_.size() ? 0 : head_ + 1;
    --count_;
  }
  if (count_ == 0) in_flight_kg_ = 0.0;  // no rounding residue once the column is empty
  return landing;
}

}  // namespace dynweigh::sim
