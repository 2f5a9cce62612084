#pragma once
// Turns a sandpile run into the lumped parameters of the plant's avalanche component (thesis
// example 3.2: "if added mass > critical mass, F_imp = v mdot + F_a", for an avalanche duration).
// Large avalanches are those of at least `large_size` topplings; the critical mass is the mass
// added between two of them.
#include <cstdint>

#include "dynweigh/granular/avalanche.hpp"
#include "dynweigh/granular/avalanche_force.hpp"

namespace dynweigh::granular {

struct SocLumpedParameters {
  double critical_mass_kg = 0;      // mean mass added between large avalanches
  double avalanche_force_n = 0;     // mean F_a amplitude of large avalanches
  double avalanche_duration_s = 0;  // mean duration of large avalanches
  std::int64_t large_avalanches = 0;
};

class SocCalibrator {
 public:
  SocCalibrator(AvalancheForceModel model, std::int64_t large_size) : model_(model), large_size_(large_size) {}

  // Call once per added grain, in order, with the avalanche that grain caused.
  void record(const Avalanche& avalanche);
  SocLumpedParameters result() const;

 private:
  AvalancheForceModel model_;
  std::int64_t large_size_;
  std::int64_t grains_ = 0;
  std::int64_t grain_of_last_large_ = -1;
  std::int64_t intervals_ = 0;
  double interval_grains_sum_ = 0;
  double force_sum_ = 0;
  double duration_sum_ = 0;
  std::int64_t large_ = 0;
};

}  // namespace dynweigh::granular
