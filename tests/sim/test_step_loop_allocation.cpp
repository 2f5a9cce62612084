// The plant allocates at set-up only (DESIGN: "it may allocate at set-up; its step loop should
// not"). Counted through the global operator new of this test binary.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "plant_runs.hpp"

namespace {
std::atomic<long> g_allocations{0};
}

// The replacements pair malloc with free on purpose; GCC cannot see that and warns.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void* operator new(std::size_t size) {
  ++g_allocations;
  if (void* p = std::malloc(size ? size : 1)) return p;
  throw std::bad_alloc();
}
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  ++g_allocations;
  return std::malloc(size ? size : 1);
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
#pragma GCC diagnostic pop

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
