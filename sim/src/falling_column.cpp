#include "dynweigh/sim/falling_column.hpp"

#include <cmath>

#include "dynweigh/model/ideal_model.hpp"

namespace dynweigh::sim {

FallingColumn::FallingColumn(double g, double longest_fall_s, double step_s)
    : g_(g), ring_(static_cast<std::size_t>(std::ceil(longest_fall_s / step_s)) + 64) {}

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

FallingColumn::Landing FallingColumn::land(double time_s, double fall_height_m) {
  Landing landing;
  while (count_ > 0) {
    const Parcel& parcel = ring_[head_];
    const double elapsed = time_s - parcel.release_s;
    const double fallen = parcel.speed_m_s * elapsed + 0.5 * g_ * elapsed * elapsed;
    if (fallen < fall_height_m) break;
    landing.mass_kg += parcel.mass_kg;
    landing.momentum_n_s += parcel.mass_kg * model::impact_speed(parcel.speed_m_s, g_, fall_height_m);
    in_flight_kg_ -= parcel.mass_kg;
    head_ = (head_ + 1) % ring_.size();
    --count_;
  }
  if (count_ == 0) in_flight_kg_ = 0.0;  // no rounding residue once the column is empty
  return landing;
}

}  // namespace dynweigh::sim
