#pragma once
// The twostage baseline as an integrator first meets it: installation values, the band, every other
// parameter at its default and no trial fills. Five fills teach it its fine preact and the coarse
// stream's overrun; from the sixth on every fill, judged by the plant's true mass, must be within the
// OIML R61 X(1) initial-verification limit of its target, at every band the bench sweeps.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "dynweigh/sim/scene.hpp"
#include "fill_series.hpp"
#include "dynweigh/model/oiml_r61_class.hpp"

namespace dynweigh::tools {

inline constexpr std::uint32_t kLearningFills = 5;
inline constexpr std::uint32_t kJudgedFills = 3;
// The bands `dynweigh bench --sweep` runs for twostage, in seconds of full flow.
inline constexpr double kBands[] = {0.25, 0.5, 1.0, 1.5, 2.5};
inline constexpr double kTargets[] = {5000.0, 10000.0};

inline void expect_within_x1_after_learning(BenchStrategy strategy, const std::string& scene_name) {
  Scenario scenario;
  scenario.name = scene_name;
  scenario.scene = *sim::scene_by_name(scene_name);
  for (double target : kTargets) {
    if (target > scenario.scene.silo.fill_kg * 1000.0 * 0.9) continue;  // the silo cannot hold it
    const double limit = model::oiml_x1_limits(target).initial_verification_g;
    for (double band : kBands) {
      SeriesSpec spec;
      spec.strategy = strategy;
      spec.knob = band;
      spec.target_g = target;
      const auto errors = fills_from_defaults(spec, scenario, kLearningFills + kJudgedFills);
      std::string trace;
      for (double e : errors) trace += " " + std::to_string(std::lround(e));
      std::printf("%s %s band %.2f s, %.0f g: errors%s g (X(1): %.1f g)\n", bench_strategy_name(strategy),
                  scene_name.c_str(), band, target, trace.c_str(), limit);
      for (std::size_t i = kLearningFills; i < errors.size(); ++i) {
        EXPECT_LE(std::abs(errors[i]), limit)  // a failed fill's NaN fails too
            << scene_name << " band " << band << " s, " << target << " g, fill " << i + 1 << ":" << trace;
      }
    }
  }
}

}  // namespace dynweigh::tools
