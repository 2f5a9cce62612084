// The plant allocates at set-up only: it may allocate at set-up; its step loop must
// not. Counted through the global operator new of this test binary.
#include <gtest/gtest.h>

#include "support/counting_operator_new.hpp"

#include <cstdlib>

#include "plant_runs.hpp"

using dynweigh::testing::g_allocations;

namespace dynweigh::sim {
namespace {

TEST(StepLoop, EveryShippedSceneRunsACycleWithoutAllocating) {
  for (const std::string& name : scene_names()) {
    Plant plant(testing::shipped_scene(name), 1);
    const auto schedule = parse_valve_schedule("open@50,half@400,close@600");
    const long before = g_allocations.load();
    long samples = 0;
    run_valve_schedule(plant, schedule, 1500, [&](const JiffyRecord& r) { samples += r.sample.raw_counts != 0; });
    EXPECT_EQ(g_allocations.load() - before, 0) << name;
    EXPECT_EQ(samples, 1500) << name;
  }
}

}  // namespace
}  // namespace dynweigh::sim
