// The lumped plant's side of the DEM comparison: a dose with the DEM's schedule.
#include <cmath>

#include "dynweigh/granular/dem_calibration.hpp"
#include "dynweigh/granular/thread_cpu_time.hpp"
#include "dynweigh/sim/plant.hpp"

namespace dynweigh::granular {

DemSceneConfig dem_scene_config(const sim::Scene& scene, double close_s, double discs_across_orifice) {
  DemSceneConfig c;
  c.bore_m = scene.silo.bore_m;
  c.fall_height_m = scene.column.fall_height_m;
  c.container_width_m = scene.column.container_diameter_m;
  c.bulk_density = scene.silo.bulk_density;
  c.gravity = scene.g;
  c.valve_dead_time_s = scene.valve.dead_time_s;
  c.valve_full_stroke_s = scene.valve.full_stroke_s;
  c.close_s = close_s;
  c.discs_across_orifice = discs_across_orifice;
  return c;
}

double steady_landing_end_s(const DemSceneConfig& c) {
  constexpr double kFastOutflow_m_s = 2.0;  // above any outflow speed of a bore this size
  const double fall = (std::sqrt(kFastOutflow_m_s * kFastOutflow_m_s + 2 * c.gravity * c.fall_height_m) - kFastOutflow_m_s) / c.gravity;
  return c.close_s + c.valve_dead_time_s + fall;
}

sim::Scene rigid_scale_scene(sim::Scene scene) {
  scene.platform.rigid = true;
  return scene;
}

LumpedDose run_lumped_dose(const sim::Scene& scene, double close_s, double duration_s, double sample_period_s,
                           std::uint64_t seed) {
  LumpedDose dose;
  const double cpu_start = thread_cpu_seconds();
  sim::Plant plant(scene, seed);
  plant.command_valve(sim::ValveCommand::open);
  const auto samples = static_cast<std::size_t>(std::llround(duration_s / sample_period_s));
  const auto close_sample = static_cast<std::size_t>(std::llround(close_s / sample_period_s));
  dose.time_s.reserve(samples);
  dose.force_n.reserve(samples);
  dose.released_kg.reserve(samples);
  for (std::size_t k = 0; k < samples; ++k) {
    if (k == close_sample) plant.command_valve(sim::ValveCommand::closed);
    plant.advance(sample_period_s);
    const sim::PlantTruth& t = plant.truth();
    dose.time_s.push_back(t.time_s);
    dose.force_n.push_back(t.force_n);
    dose.released_kg.push_back(t.released_kg);
  }
  dose.cpu_seconds = thread_cpu_seconds() - cpu_start;
  return dose;
}

}  // namespace dynweigh::granular
