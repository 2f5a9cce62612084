#pragma once
// Calibration of a lumped scene from the SOC heap and from Poisson duct flow.
// SOC: the thesis' extended 2D heap, a cross-section of the container one grain per cell, fed
// at its centre; its large avalanches give the avalanche component (SocCalibrator: critical
// mass, F_a, duration) and its height against the grains added the pile height law
// h = a N^b, whose slope gives the repose angle (square cells: one grain wide and high).
// A cell stands for a grain-sized slab through the container's depth: mass rho_b d^2 D_c.
// Fluid: alpha = mean / max of the Poisson profile over the scene's round bore.
#include <cstdint>

#include "dynweigh/sim/scene.hpp"

namespace dynweigh::granular {

struct SocSceneCalibration {
  sim::Scene scene;
  double critical_kg = 0, force_n = 0, duration_s = 0;
  std::int64_t large_avalanches = 0;
  double height_exponent = 0;  // b of h = a N^b (1/2 for a heap of constant slope)
  double height_slope = 0;     // the heap's slope (height per column), from h^2 = slope N
  double repose_angle_deg = 0;
  std::int64_t columns = 0, grains = 0;
  double cell_mass_kg = 0;
};
// `grains` added at the centre; `large_size`: topplings of an avalanche that counts as large
// (0: a quarter of the columns); `critical_step` of the heap.
SocSceneCalibration calibrate_from_soc(const sim::Scene& base, std::int64_t grains, std::int64_t large_size,
                                       int critical_step, std::uint64_t seed);

struct FluidSceneCalibration {
  sim::Scene scene;
  double alpha = 0;
  int grid = 0;
  int iterations = 0;
};
FluidSceneCalibration calibrate_from_fluid(const sim::Scene& base, int grid);

}  // namespace dynweigh::granular
