// `dose` on the simulated plant (the default scene unless a test says otherwise), judged by the
// plant's true mass, never the firmware's claim.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "support/console_session.hpp"

namespace dynweigh::testing {
namespace {

struct Fill {
  double true_error_g;
  long reported_error_g;
  double time_s;
};

Fill dose(const std::string& command, std::uint64_t seed) {
  ConsoleSession c(sim::default_scene(), seed);
  c.idle(20);  // the display filter settles on the empty scale
  const double before = c.session().plant().truth().static_kg;
  const auto lines = lines_of(c.run({command}));
  EXPECT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines.back(), "OK");
  const std::string result = lines.empty() ? "" : lines.front();
  EXPECT_EQ(result.rfind("RESULT target=", 0), 0u) << result;
  // Everything released must have landed by the time the result is certified.
  EXPECT_LT(c.session().plant().truth().in_flight_kg, 1e-9);
  const double fill_g = (c.session().plant().truth().static_kg - before) * 1000.0;
  const long target = std::stol(field(result, "target"));
  return {fill_g - double(target), std::stol(field(result, "error")), std::stod(field(result, "time")) / 1000.0};
}

struct Spread {
  double mean = 0, sd = 0, worst = 0, mean_time = 0, reported_vs_true = 0;
};

Spread over_seeds(const std::string& command, int seeds) {
  std::vector<Fill> fills;
  for (int s = 1; s <= seeds; ++s) fills.push_back(dose(command, std::uint64_t(s)));
  Spread spread;
  for (const auto& f : fills) {
    spread.mean += f.true_error_g / seeds;
    spread.mean_time += f.time_s / seeds;
    spread.worst = std::max(spread.worst, std::abs(f.true_error_g));
    spread.reported_vs_true = std::max(spread.reported_vs_true, std::abs(double(f.reported_error_g) - f.true_error_g));
  }
  for (const auto& f : fills) spread.sd += (f.true_error_g - spread.mean) * (f.true_error_g - spread.mean);
  spread.sd = std::sqrt(spread.sd / (seeds - 1));
  std::printf("%s: true error mean %.1f g, sd %.1f g, worst %.1f g; time %.2f s; |reported - true| <= %.1f g\n",
              command.c_str(), spread.mean, spread.sd, spread.worst, spread.mean_time, spread.reported_vs_true);
  return spread;
}

TEST(Dose, ModelStrategyFills10kgWithin100gOver20Seeds) {
  const Spread model = over_seeds("dose 10000 model", 20);
  EXPECT_LE(model.worst, 100.0);
  // The certified result is the scale's reading of the true fill: within a few divisions, and
  // certified dynamically, seconds before the platform has stopped ringing.
  EXPECT_LE(model.reported_vs_true, 3.0);
  EXPECT_LT(model.mean_time, 6.0);
}

TEST(Dose, PreactStrategyIsMeasuredBesideIt) {
  const Spread preact = over_seeds("dose 10000 preact", 20);
  // With its default preact (tuned on this scene) the baseline also lands near the target; this
  // pins that the yardstick is honest, not that it is good.
  EXPECT_LE(std::abs(preact.mean), 100.0);
  EXPECT_LE(preact.reported_vs_true, 3.0);
}

TEST(Dose, DefaultIsTheModelStrategy) {
  ConsoleSession c;
  EXPECT_EQ(field(lines_of(c.run({"dose 3000"}))[0], "strategy"), "model");
}

TEST(Dose, EveryStrategyOfTheSpecDoses) {
  for (const char* strategy : {"model", "preact", "twostage", "learn"}) {
    ConsoleSession c;
    const auto lines = lines_of(c.run({std::string("dose 3000 ") + strategy}));
    ASSERT_EQ(lines.size(), 2u) << strategy;
    EXPECT_EQ(field(lines[0], "strategy"), strategy);
    EXPECT_EQ(c.session().last_row().valve, 0);
  }
}

// The valve opens only from a scale at rest (stable_band_g for stable_ms): a dose sent while the
// reading still moves waits, and its start weight, and so its fill, is the one at rest.
TEST(Dose, OpensOnlyOnceTheScaleIsAtRest) {
  ConsoleSession moving;  // sent at power-up: the display filter is still rising to the empty hopper
  const auto moving_result = lines_of(moving.run({"dose 3000"}));
  ASSERT_EQ(moving_result.size(), 2u);
  std::size_t first_open = 0;
  while (first_open < moving.trace().size() && moving.trace()[first_open].valve == 0) ++first_open;
  EXPECT_GE(first_open, 49u) << "opened before the 0.5 s of rest (the 50th sample at rest is jiffy 49)";
  EXPECT_LE(first_open, 150u) << "waited far longer than the filter takes to settle";

  ConsoleSession resting;
  resting.idle(200);
  const std::size_t before = resting.trace().size();
  const auto resting_result = lines_of(resting.run({"dose 3000"}));
  ASSERT_EQ(resting_result.size(), 2u);
  EXPECT_EQ(resting.trace()[before].valve, 2) << "a scale at rest opens in the dose's own jiffy";
  // Both fills are right: the wait cost time, not accuracy.
  for (ConsoleSession* c : {&moving, &resting}) {
    const double fill_g = c->session().plant().truth().static_kg * 1000.0;
    EXPECT_NEAR(fill_g, 3000.0, 100.0);
  }
}

// Doses into one container, 30 kg in the end: the loaded platform rings at ~5 Hz with a damping
// ratio of 0.02 and swings more than the flow-after-close threshold through the display filter; the
// supervisor's period mean sees through it (seeds that raised a false flow_after_close before).
TEST(Dose, FiveDosesIntoOneContainerRaiseNoFalseFault) {
  sim::Scene scene = sim::default_scene();
  scene.silo.fill_kg = 40.0;
  for (std::uint64_t seed : {1u, 3u, 4u}) {
    ConsoleSession c(scene, seed);
    c.idle(20);
    for (int dose = 1; dose <= 5; ++dose) {
      const auto lines = lines_of(c.run({"dose 6000"}));
      ASSERT_EQ(lines.size(), 2u) << "seed " << seed << ", dose " << dose << ": " << lines.front();
      EXPECT_EQ(lines.front().rfind("RESULT", 0), 0u) << lines.front();
    }
    EXPECT_NEAR(c.session().plant().truth().static_kg, 30.0, 0.3);
    EXPECT_EQ(field(lines_of(c.run({"status"})).front(), "fault"), "none");
  }
}

// `fine-powder` lands its grains on an impact that relaxes over 80 ms: after the last grain the
// reading is the fill, the platform's ringing and that force dying away. A fit of the ringing alone
// followed it down slowly, and its estimates agreed while still 3.4 to 5.2 g high: the top-ups
// stopped short. Certified only once the fit's residuals are near the noise the scale showed at
// rest, the 500 g fills' results (pulses and all) are the true fill within 2.5 g each and within
// 1.5 g on average.
TEST(Dose, ARelaxingImpactIsNotCertifiedUntilTheFitDescribesTheReading) {
  ConsoleSession c(*sim::scene_by_name("fine-powder"), 1);
  c.run({"param density 600", "param repose_deg 40"});  // the installer's word for the powder
  c.idle(100);
  double worst_g = 0.0, sum_g = 0.0;
  int pulses = 0;
  for (int fill = 1; fill <= 6; ++fill) {
    const double before_kg = c.session().plant().truth().static_kg;
    const auto lines = lines_of(c.run({"dose 500"}));
    ASSERT_EQ(lines.size(), 2u) << "fill " << fill << ": " << (lines.empty() ? "" : lines.front());
    ASSERT_EQ(lines.front().rfind("RESULT", 0), 0u) << lines.front();
    const double true_g = (c.session().plant().truth().static_kg - before_kg) * 1000.0;
    const double claim_error_g = std::stod(field(lines.front(), "final")) - true_g;
    std::printf("fill %d: %s; true fill %.1f g, certified %+.1f g off\n", fill, lines.front().c_str(), true_g,
                claim_error_g);
    worst_g = std::max(worst_g, std::abs(claim_error_g));
    sum_g += claim_error_g;
    pulses += std::stoi(field(lines.front(), "topups"));
  }
  EXPECT_GE(pulses, 6) << "the fills were to be finished by top-ups, each certified after its pulse";
  EXPECT_LE(worst_g, 2.5);
  EXPECT_LE(std::abs(sum_g / 6.0), 1.5);
}

// A blank indicator commissioned through the console (`zero`, a test weight, `cal`) doses in the
// same power cycle. Its rests before the span read 0 g (no grams without a calibration): the noise
// at rest the dynamic certification measures itself against must be the scale's under its span, or
// every fit's residuals look too large and the result waits (5.78 s against 5.01 s when the rests
// without a span counted).
TEST(Dose, CommissionedAndDosedWithoutARestartItCertifiesAsSoonAsCalibratedAtTheFactory) {
  ConsoleSession factory(sim::default_scene(), 1);
  factory.idle(400);
  const auto factory_lines = lines_of(factory.run({"dose 10000"}));
  ASSERT_EQ(factory_lines.size(), 2u);

  ConsoleSession blank(sim::default_scene(), 1, firmware::PersistentSettings{});
  blank.idle(100);
  ASSERT_EQ(lines_of(blank.run({"zero"})).back(), "OK");
  blank.session().plant().place_test_weight(20.0);
  blank.idle(500);
  ASSERT_EQ(lines_of(blank.run({"cal 20000"})).back(), "OK");
  blank.session().plant().place_test_weight(0.0);  // lifted at once, the platform swings below zero
  blank.idle(400);
  ASSERT_EQ(lines_of(blank.run({"clearfault"})).back(), "OK");  // the underload that swing raised
  blank.idle(200);
  const auto lines = lines_of(blank.run({"dose 10000"}));
  ASSERT_EQ(lines.size(), 2u) << (lines.empty() ? "" : lines.front());
  ASSERT_EQ(lines.front().rfind("RESULT", 0), 0u) << lines.front();
  std::printf("factory: %s\ncommissioned: %s\n", factory_lines.front().c_str(), lines.front().c_str());
  EXPECT_LE(std::stod(field(lines.front(), "time")), std::stod(field(factory_lines.front(), "time")) + 300.0);
}

}  // namespace
}  // namespace dynweigh::testing
