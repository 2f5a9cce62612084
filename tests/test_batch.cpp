// The batch: `batch <m>:<g> ...` doses each ingredient in turn into the one hopper, material m from
// its own valve, each target on top of the weight before it; a RESULT per ingredient with its
// material, then BATCH and OK. Bad recipes open nothing; a fault or `abort` ends the batch with
// BATCH ok=0 and every valve closed; the operator's material selection comes back.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "dynweigh/firmware/batch_cycle.hpp"
#include "dynweigh/model/oiml_r61_limits.hpp"
#include "support/console_session.hpp"

namespace dynweigh::testing {
namespace {

using firmware::BatchCycle;
using firmware::BatchIngredient;
using firmware::BatchWordError;

BatchWordError parse(const char* word, BatchIngredient& out) { return BatchCycle::parse(word, 30000, out); }

TEST(BatchCycleParse, TakesMaterialColonGrams) {
  BatchIngredient in;
  ASSERT_EQ(parse("2:1500", in), BatchWordError::none);
  EXPECT_EQ(in.material, 2);
  EXPECT_EQ(in.grams, 1500);
  ASSERT_EQ(parse("7:30000", in), BatchWordError::none);
  EXPECT_EQ(in.material, 7);
  EXPECT_EQ(in.grams, 30000);
}

TEST(BatchCycleParse, RefusesWhatIsNotOneIngredient) {
  BatchIngredient in;
  for (const char* word : {"2", "2-1500", ":1500", "2:", "a:100", "2:1.5", "2:+100", "-1:100", "2:100:3", "2:1e3"}) {
    EXPECT_EQ(parse(word, in), BatchWordError::form) << word;
  }
  EXPECT_EQ(parse("8:100", in), BatchWordError::material);
  EXPECT_EQ(parse("15:100", in), BatchWordError::material);
  EXPECT_EQ(parse("1:0", in), BatchWordError::grams);
  EXPECT_EQ(parse("1:30001", in), BatchWordError::grams);
  EXPECT_EQ(parse("1:99999999999", in), BatchWordError::form);  // longer than any weight
}

TEST(BatchCycle, CountsEachIngredientAndEndsAfterTheLast) {
  const BatchIngredient recipe[] = {{0, 2000}, {1, 1500}, {2, 1000}};
  BatchCycle batch;
  ASSERT_TRUE(batch.start(recipe, 3, 5, 100));
  EXPECT_TRUE(batch.active());
  EXPECT_EQ(batch.current().material, 0);
  EXPECT_TRUE(batch.next(2003));
  EXPECT_EQ(batch.current().material, 1);
  EXPECT_EQ(batch.current().grams, 1500);
  EXPECT_TRUE(batch.next(1498));
  EXPECT_EQ(batch.current().material, 2);
  EXPECT_FALSE(batch.next(1001));
  const BatchCycle::Summary s = batch.finish(350);
  EXPECT_FALSE(batch.active());
  EXPECT_EQ(s.ingredients, 3u);
  EXPECT_EQ(s.total_g, 2003 + 1498 + 1001);
  EXPECT_EQ(s.jiffies, 250u);
  EXPECT_EQ(batch.operator_material(), 5u);
}

TEST(BatchCycle, StoppedEarlyCountsOnlyTheCertifiedOnes) {
  const BatchIngredient recipe[] = {{0, 2000}, {1, 1500}};
  BatchCycle batch;
  ASSERT_TRUE(batch.start(recipe, 2, 0, 0));
  EXPECT_TRUE(batch.next(1990));
  const BatchCycle::Summary s = batch.finish(10);
  EXPECT_EQ(s.ingredients, 1u);
  EXPECT_EQ(s.total_g, 1990);
}

TEST(BatchCycle, RefusesAnEmptyOrTooLongRecipe) {
  BatchIngredient recipe[BatchCycle::kMaxIngredients + 1];
  BatchCycle batch;
  EXPECT_FALSE(batch.start(recipe, 0, 0, 0));
  EXPECT_FALSE(batch.start(recipe, BatchCycle::kMaxIngredients + 1, 0, 0));
  EXPECT_FALSE(batch.active());
}

sim::Scene batching_scene() { return *sim::scene_by_name("batching"); }

double released_kg(ConsoleSession& s) {
  double kg = 0.0;
  for (const auto& ingredient : s.session().plant().truth().ingredients) kg += ingredient.released_kg;
  return kg;
}

void expect_every_valve_closed(ConsoleSession& s) {
  EXPECT_EQ(s.session().last_record().outputs.valve, firmware::ValveCommand::closed);
  s.idle(100);  // the slowest valve strokes in 0.2 s
  const sim::Plant& plant = s.session().plant();
  for (std::size_t i = 0; i < plant.ingredient_count(); ++i) {
    EXPECT_EQ(plant.ingredient_valve_feedback(i), firmware::ValvePosition::closed) << "valve " << i;
  }
}

// What the plant says each ingredient delivered: each ingredient's released mass, all landed.
double delivered_g(ConsoleSession& s, std::size_t ingredient) {
  return 1000.0 * s.session().plant().truth().ingredients[ingredient].released_kg;
}

TEST(Batch, DosesEachIngredientFromItsOwnValveOnTopOfTheLast) {
  ConsoleSession s(batching_scene());
  s.run({"material 4"});  // the operator's selection
  const std::string out = s.run({"batch 0:2000 1:1500 2:1000"});
  const auto results = lines_starting(out, "RESULT ");
  ASSERT_EQ(results.size(), 3u) << out;
  const int targets[] = {2000, 1500, 1000};
  long total = 0;
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(field(results[i], "target"), std::to_string(targets[i])) << results[i];
    EXPECT_EQ(field(results[i], "material"), std::to_string(i)) << results[i];
    const long final_g = std::stol(field(results[i], "final"));
    total += final_g;
    // Each ingredient came from its own valve, and its result is its own (not the hopper's total).
    EXPECT_NEAR(delivered_g(s, i), double(final_g), 5.0) << results[i];
  }
  const auto batch = lines_starting(out, "BATCH ");
  ASSERT_EQ(batch.size(), 1u) << out;
  EXPECT_EQ(field(batch[0], "ingredients"), "3");
  EXPECT_EQ(field(batch[0], "total_g"), std::to_string(total));
  EXPECT_EQ(field(batch[0], "ok"), "1");
  EXPECT_GT(std::stol(field(batch[0], "time")), 0);
  EXPECT_EQ(lines_of(out).back(), "OK");
  // Cumulative weighing: no tare between, the scale shows the whole batch (once the platform is still).
  s.idle(300);
  const std::string status = s.run({"status"});
  EXPECT_NEAR(std::stod(field(lines_of(status)[0], "weight")), 1000.0 * s.session().plant().truth().static_kg, 5.0)
      << status;
  // Each ingredient counted and logged under its material; the operator's selection back.
  for (int m = 0; m < 3; ++m) {
    const std::string stats = s.run({"stats " + std::to_string(m)});
    EXPECT_EQ(field(lines_of(stats)[0], "count"), "1") << stats;
  }
  const std::string log = s.run({"log 3"});
  const auto logged = lines_starting(log, "LOG ");
  ASSERT_EQ(logged.size(), 3u) << log;
  for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(field(logged[i], "material"), std::to_string(i)) << logged[i];
  EXPECT_NE(s.run({"material"}).find("MATERIAL n=4 name=material4 density=1550 class=1 fills=0 selected=1"),
            std::string::npos);
  expect_every_valve_closed(s);
}

// The next ingredient's valve is another valve (barley's and flour's stroke slower than sand's), and
// it opens while the last close's after-close watch still runs: neither is a fault.
TEST(Batch, EachIngredientsValveIsJudgedOnItsOwn) {
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    ConsoleSession s(batching_scene(), seed);
    const std::string out = s.run({"batch 0:10000 1:5000 2:4000"});
    const auto batch = lines_starting(out, "BATCH ");
    ASSERT_EQ(batch.size(), 1u) << out;
    EXPECT_EQ(field(batch[0], "ok"), "1") << "seed " << seed << "\n" << out;
  }
}

// Batch after batch, each emptied through the gate and each silo refilled from upstream: the first
// batch is each material's first fill (barley's 80 mm bore and flour's slow stroke are not what the
// installation's parameters describe), and what it measured, kept per material, brings every
// ingredient of the later batches within its X(1), by the plant's truth.
TEST(Batch, FromTheSecondBatchEveryIngredientIsWithinItsX1) {
  sim::Scene scene = batching_scene();
  scene.silo.refill_below_kg = 15.0;
  for (sim::IngredientParameters& ingredient : scene.ingredients) ingredient.silo.refill_below_kg = 7.0;
  const int targets[] = {10000, 5000, 4000};
  for (std::uint64_t seed = 2; seed <= 4; ++seed) {
    ConsoleSession s(scene, seed);
    s.run({"material 1 density 700", "material 2 density 500"});
    for (int batch = 1; batch <= 3; ++batch) {
      double before_g[3];
      for (std::size_t i = 0; i < 3; ++i) before_g[i] = delivered_g(s, i);
      const std::string out = s.run({"batch 0:10000 1:5000 2:4000"});
      ASSERT_EQ(lines_starting(out, "RESULT ").size(), 3u) << out;
      for (std::size_t i = 0; batch > 1 && i < 3; ++i) {
        const double error_g = delivered_g(s, i) - before_g[i] - targets[i];
        EXPECT_LE(std::fabs(error_g), model::oiml_r61_x1_limits(double(targets[i])).initial_verification_g)
            << "seed " << seed << " batch " << batch << " ingredient " << i;
      }
      ASSERT_EQ(s.run({"discharge"}), "OK\n") << "seed " << seed << " batch " << batch;
    }
  }
}

TEST(Batch, ABadRecipeOpensNothing) {
  ConsoleSession s(batching_scene());
  const std::vector<std::pair<std::string, std::string>> refused = {
      {"batch", "ERR 2 usage: batch"},
      {"batch 1-1500", "ERR 2 usage: batch"},
      {"batch 0:2000 1", "ERR 2 usage: batch"},
      {"batch 0:2000 1:", "ERR 2 usage: batch"},
      {"batch 0:0", "ERR 2 grams out of range"},
      {"batch 0:-5", "ERR 2 usage: batch"},
      {"batch 0:60000", "ERR 2 grams out of range"},
      {"batch 8:100", "ERR 2 material 0..7"},
      {"batch 3:100", "ERR 2 no valve for that material"},  // the scene has valves 0..2
      {"batch 0:100 0:100 0:100 0:100 0:100 0:100 0:100 0:100 0:100", "ERR 2 at most 8 ingredients"},
      {"batch 0:100 1:100 fast", "ERR 2 unknown strategy"},
      {"batch 0:30000 1:30000", "ERR 2 the batch exceeds the scale's capacity"},
  };
  for (const auto& [line, answer] : refused) {
    const std::string out = s.run({line});
    EXPECT_EQ(out.rfind(answer, 0), 0u) << line << " -> " << out;
  }
  s.idle(100);
  EXPECT_EQ(released_kg(s), 0.0);
}

TEST(Batch, AFaultStopsTheBatchWithEveryValveClosed) {
  sim::Scene scene = batching_scene();
  scene.ingredients[1].silo.fill_kg = 0.02;  // barley's silo is all but empty: nothing comes
  ConsoleSession s(scene);
  const std::string out = s.run({"batch 0:2000 1:1500 2:1000"});
  const auto lines = lines_of(out);
  ASSERT_GE(lines.size(), 3u) << out;
  EXPECT_EQ(lines_starting(out, "RESULT ").size(), 1u) << out;
  const auto batch = lines_starting(out, "BATCH ");
  ASSERT_EQ(batch.size(), 1u) << out;
  EXPECT_EQ(field(batch[0], "ingredients"), "1");
  EXPECT_EQ(field(batch[0], "ok"), "0");
  EXPECT_EQ(lines[lines.size() - 2].rfind("BATCH ", 0), 0u) << out;
  EXPECT_EQ(lines.back().rfind("ERR 4 fault ", 0), 0u) << out;
  EXPECT_EQ(delivered_g(s, 2), 0.0);  // flour never opened
  expect_every_valve_closed(s);
}

TEST(Batch, AbortStopsTheBatchWithEveryValveClosed) {
  ConsoleSession s(batching_scene());
  std::string out = s.run({"batch 0:2000 1:1500 2:1000"}, 1);
  // Run until the second ingredient's valve is open, then abort (sent as it comes: a script would
  // wait for the batch to end).
  for (int i = 0; i < 20000 && s.session().plant().ingredient_valve_feedback(1) != firmware::ValvePosition::open; ++i) {
    s.step();
  }
  ASSERT_EQ(s.session().plant().ingredient_valve_feedback(1), firmware::ValvePosition::open);
  out = s.send_raw("abort\n", 5);
  const auto lines = lines_of(out);
  ASSERT_EQ(lines.size(), 3u) << out;
  EXPECT_EQ(lines[0].rfind("BATCH ingredients=1 ", 0), 0u) << out;
  EXPECT_EQ(field(lines[0], "ok"), "0");
  EXPECT_EQ(lines[1], "ERR 3 aborted");
  EXPECT_EQ(lines[2], "OK");
  expect_every_valve_closed(s);
  EXPECT_EQ(delivered_g(s, 2), 0.0);
  EXPECT_NE(s.run({"status"}).find("fault=none"), std::string::npos);
}

TEST(Batch, IsListedByHelp) {
  ConsoleSession s;
  EXPECT_NE(s.run({"help"}).find("\nbatch <m>:<g> "), std::string::npos);
}

}  // namespace
}  // namespace dynweigh::testing
