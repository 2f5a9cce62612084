#pragma once
// The falling stream as parcels: each leaves the orifice with its own speed and lands when it
// reaches the pile top *at that moment*, so the mass in flight is exact and the landing rate
// exceeds the release rate while the pile rises (thesis §1.3, the 10 kg / 9 s example).
//
// A parcel's landing instant inside the step is solved exactly for the present fall height, and
// its landing speed is v0 + g * (time in the air): the momentum it brings and the time it spent
// off the scale always agree, which is what keeps the hourglass' impulse balance exact.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace dynweigh::sim {

class FallingColumn {
 public:
  // Sized at set-up for `capacity` parcels; the step loop never allocates.
  FallingColumn(double g, std::size_t capacity);

  void release(double time_s, double mass_kg, double speed_m_s);

  struct Landing {
    double mass_kg = 0.0;
    double momentum_n_s = 0.0;    // mass times impact speed, summed
    double resting_kg_s = 0.0;    // sum of mass times the time it rests on the scale within the step
    double resting_momentum_n_s2 = 0.0;  // the same for the momentum brought
  };
  // Lands every parcel that has fallen `fall_height_m` by `step_end_s`.
  Landing land(double step_begin_s, double step_end_s, double fall_height_m);

  double in_flight_kg() const { return in_flight_kg_; }
  std::size_t parcels() const { return count_; }
  std::uint64_t steps() const { return steps_; }

 private:
  struct Parcel {
    double release_s;
    double mass_kg;
    double speed_m_s;
  };
  double g_;
  std::vector<Parcel> ring_;
  std::size_t head_ = 0;  // oldest
  std::size_t count_ = 0;
  double in_flight_kg_ = 0.0;
  std::uint64_t steps_ = 0;
};

}  // namespace dynweigh::sim
