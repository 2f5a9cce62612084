#include "dynweigh/granular/soc_calibration.hpp"

namespace dynweigh::granular {

void SocCalibrator::record(const Avalanche& avalanche) {
  ++grains_;
  if (avalanche.size < large_size_ || !avalanche.happened()) return;
  ++large_;
  force_sum_ += model_.amplitude_n(avalanche);
  duration_sum_ += model_.duration_s(avalanche);
  if (grain_of_last_large_ >= 0) {
    interval_grains_sum_ += static_cast<double>(grains_ - grain_of_last_large_);
    ++intervals_;
  }
  grain_of_last_large_ = grains_;
}

SocLumpedParameters SocCalibrator::result() const {
  SocLumpedParameters p;
  p.large_avalanches = large_;
  if (large_ > 0) {
    p.avalanche_force_n = force_sum_ / static_cast<double>(large_);
    p.avalanche_duration_s = duration_sum_ / static_cast<double>(large_);
  }
  if (intervals_ > 0) {
    p.critical_mass_kg = interval_grains_sum_ / static_cast<double>(intervals_) * model_.grain_mass_kg;
  }
  return p;
}

}  // namespace dynweigh::granular
