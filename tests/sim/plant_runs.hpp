#pragma once
// Helpers the plant suites share: run a scene through a valve schedule to a given time.
#include <cstdint>
#include <stdexcept>
#include <string>

#include "dynweigh/sim/plant.hpp"
#include "dynweigh/sim/scene.hpp"
#include "dynweigh/sim/valve_schedule.hpp"

namespace dynweigh::sim::testing {

inline Scene shipped_scene(const std::string& name) {
  const auto scene = scene_by_name(name);
  if (!scene) throw std::runtime_error("no scene " + name);
  return *scene;
}

// The thesis' standard cycle: starttestdata 50 600.
inline const char* kStandardSchedule = "open@50,close@600";

}  // namespace dynweigh::sim::testing
