#pragma once
// The falling stream as parcels: each leaves the orifice with its own speed and lands when it
// reaches the pile top *at that moment*, so the mass in flight is exact and the landing rate
// exceeds the release rate while the pile rises (thesis §1.3, the 10 kg / 9 s example).
#include <cstddef>
#include <vector>

namespace dynweigh::sim {

class FallingColumn {
 public:
  // Sized at set-up for the longest fall a scene allows; the step loop never allocates.
  FallingColumn(double g, double longest_fall_s, double step_s);

  void release(double time_s, double mass_kg, double speed_m_s);

  struct Landing {
    double mass_kg = 0.0;
    double momentum_n_s = 0.0;  // mass times impact speed, summed
  };
  // Lands every parcel at the front that has fallen `fall_height_m` by `time_s`.
  Landing land(double time_s, double fall_height_m);

  double in_flight_kg() const { return in_flight_kg_; }
  std::size_t parcels() const { return count_; }

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
};

}  // namespace dynweigh::sim
