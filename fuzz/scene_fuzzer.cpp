// Fuzz target: arbitrary bytes as a scene file (sim/scene_file.hpp), the text `dynweigh sim --scene`
// and `dynweigh-fw --plant sim:FILE` read.
//
// Invariants: the parser either refuses with std::runtime_error (the one-line message the tools
// print) or returns a scene that passes validate_scene and describe_scene; any other exception, a
// crash or undefined behaviour is a finding. An accepted scene builds a plant that runs a short
// open-and-close cycle with finite forces and masses, and a sample the load cell can report.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "dynweigh/sim/plant.hpp"
#include "dynweigh/sim/scene_file.hpp"

namespace {

using namespace dynweigh::sim;

[[noreturn]] void violated(const char* what) {
  std::fprintf(stderr, "scene invariant violated: %s\n", what);
  std::abort();
}

// Bounded in internal steps, not time: a scene may step at 1 us.
constexpr double kMaxInternalSteps = 2000;

void check_plant_runs(const Scene& scene) {
  Plant plant(scene, 1);
  const double open_s = std::min(0.1, kMaxInternalSteps / 2 * scene.internal_step_s);
  plant.command_valve(ValveCommand::open);
  plant.advance(open_s);
  plant.command_valve(ValveCommand::closed);
  plant.advance(open_s);
  const PlantTruth& t = plant.truth();
  for (const double value : {t.released_kg, t.static_kg, t.in_flight_kg, t.force_n, t.silo_kg, t.fall_height_m}) {
    if (!std::isfinite(value)) violated("an accepted scene's plant computed a value that is not finite");
  }
  plant.sample();
  if (!std::isfinite(plant.empty_counts()) || !std::isfinite(plant.counts_per_gram())) {
    violated("an accepted scene's calibration is not finite");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  Scene scene;
  try {
    scene = parse_scene_json(text, "fuzz.json");
  } catch (const std::runtime_error& refused) {
    if (std::string(refused.what()).find('\n') != std::string::npos) violated("a refusal of more than one line");
    return 0;
  }
  try {
    validate_scene(scene, "fuzz.json");
  } catch (const std::runtime_error&) {
    violated("an accepted scene fails validation");
  }
  describe_scene(scene);
  check_plant_runs(scene);
  return 0;
}
