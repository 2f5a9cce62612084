// The final-weight predictor, configured by its plain struct: the prior before the stream is
// measured, the ideal model with the corrected sign once it is, the fine feed, the settling time.
#include <gtest/gtest.h>

#include "dynweigh/firmware/final_weight_predictor.hpp"
#include "dynweigh/firmware/model_cutoff.hpp"
#include "dynweigh/firmware/parameters.hpp"
#include "dynweigh/model/gravity.hpp"
#include "dynweigh/model/ideal_model.hpp"

namespace dynweigh::firmware {
namespace {

using Predictor = BasicFinalWeightPredictor<double>;
using Config = FinalWeightPredictorConfig<double>;

BasicLearnedValveTiming<double> datasheet_valve() {
  BasicLearnedValveTiming<double> valve;
  valve.configure(ValveDatasheet<double>{}, Config{}.material, Config{}.bore_m);
  valve.start_dose();
  return valve;
}

DoseValveTiming<double> datasheet_timing() { return datasheet_valve().in_use(); }
const model::GateFlowShape<double> kShape = datasheet_valve().gate_flow_shape();

Predictor started(const Config& config, double start_weight_g = 0.0) {
  Predictor p;
  p.configure(config);
  p.start(start_weight_g, datasheet_timing());
  return p;
}

// The struct's defaults are the parameters' defaults: before the first impact, the strategy with
// default parameters predicts what the predictor with a default struct does.
TEST(FinalWeightPredictor, TheConfigDefaultsAreTheParameterDefaults) {
  BasicModelCutoff<double> cutoff;
  cutoff.configure(Parameters{});
  cutoff.start(0.0);
  const Predictor predictor = started(Config{});
  for (std::uint32_t jiffy = 1; jiffy <= 5; ++jiffy) {
    EXPECT_NEAR(cutoff.observe(0.0), predictor.from_prior(jiffy, kShape), 1e-3) << "jiffy " << jiffy;
  }
  EXPECT_NEAR(cutoff.settle_delay_s(), predictor.settle_delay_s(), 1e-9);
  for (const double on_scale_g : {0.0, 5000.0, 30000.0}) {
    EXPECT_NEAR(cutoff.fall_height_m(on_scale_g), predictor.fall_height_m(on_scale_g), 1e-9) << on_scale_g << " g";
  }
}

// Before the stream is measured: once the gate has travelled its stroke, the prior flow's open time
// less the flow missing at the opening, plus the let-through at the close.
TEST(FinalWeightPredictor, ThePriorGrowsAtThePriorFlowOnceTheGateIsFullOpen) {
  const Config config;
  const Predictor p = started(config);
  const DoseValveTiming<double> timing = datasheet_timing();
  const double prior_g_s = 1000.0 * p.prior_rate_kg_s();
  EXPECT_NEAR(p.from_prior(101, kShape), prior_g_s * (1.0 - timing.opening_delay_s + timing.full_closing_flow_s), 1e-9);
  EXPECT_NEAR(p.from_prior(101, kShape) - p.from_prior(100, kShape), prior_g_s * config.jiffy_s, 1e-9);
  EXPECT_NEAR(p.prior_growth_per_jiffy_g(100, kShape), prior_g_s * config.jiffy_s, 1e-9);
  EXPECT_NEAR(p.growth_per_jiffy_g(), prior_g_s * config.jiffy_s, 1e-9);
  // A larger bore brings more.
  Config wide = config;
  wide.bore_m = 2.0 * config.bore_m;
  EXPECT_GT(started(wide).prior_rate_kg_s(), 4.0 * p.prior_rate_kg_s());
}

// A close commanded before the gate has travelled its stroke (80 ms on the datasheet): the gate goes
// on opening for the dead time, to the share of its stroke the open time is, and closes from there.
// With a flow in proportion to the stroke that passes t^2 / stroke seconds of the full flow: 20 ms
// open lets 5 ms of it through, not the 20 ms less the flow missing at the opening the full-open
// reckoning would give (nothing at all, or the whole let-through at once). Continuous at full stroke.
TEST(FinalWeightPredictor, ACloseBeforeTheGateIsFullOpenPassesWhatItsPartialStrokeLetsThrough) {
  const Config config;
  const Predictor p = started(config);
  const DoseValveTiming<double> timing = datasheet_timing();
  ASSERT_NEAR(timing.stroke_s, 0.08, 1e-12);
  const double prior_g_s = 1000.0 * p.prior_rate_kg_s();
  const auto proportional = model::GateFlowShape<double>::proportional();
  EXPECT_NEAR(p.from_prior(1, proportional), 0.0, 1e-12);  // commanded shut as it was opened: nothing moves
  EXPECT_NEAR(p.from_prior(3, proportional), prior_g_s * 0.02 * 0.02 / 0.08, 1e-9);
  EXPECT_NEAR(p.prior_growth_per_jiffy_g(3, proportional), prior_g_s * 0.01 * 2.0 * 0.25, 1e-9);
  // The real gate's flow grows faster than its stroke: less still passes part-way.
  EXPECT_LT(p.from_prior(3, kShape), p.from_prior(3, proportional));
  EXPECT_GT(p.from_prior(3, kShape), 0.0);
  for (const auto& shape : {proportional, kShape}) {
    const double before = p.from_prior(8, shape), at_end = p.from_prior(9, shape), after = p.from_prior(10, shape);
    EXPECT_NEAR(at_end, prior_g_s * (0.08 - timing.opening_delay_s + timing.full_closing_flow_s), 1e-9);
    EXPECT_LT(before, at_end);
    EXPECT_NEAR(after - at_end, prior_g_s * config.jiffy_s, 1e-9);
  }
}

// The ideal model's corrected sign: closed now, the fill ends mdot v0 / g below the reading (the
// impulse outweighs what is still in flight), plus the valve's let-through.
TEST(FinalWeightPredictor, TheIdealModelWithTheCorrectedSign) {
  Config config;
  config.pile_grows = false;
  Predictor p = started(config, 1000.0);
  const double rate_g_per_jiffy = 24.0;
  const double equilibrium_g = 6000.0;
  const double predicted = p.from_observer(equilibrium_g, rate_g_per_jiffy, rate_g_per_jiffy);

  const double rate_kg_s = rate_g_per_jiffy / (1000.0 * config.jiffy_s);
  const double v0 = model::outflow_speed(rate_kg_s, p.full_open_geometry().bore_area_m2, config.material.bulk_density);
  const double excess_kg = model::reading_excess_at_close_kg(rate_kg_s, v0, model::kGravity<double>);
  const double let_through_kg = rate_kg_s * datasheet_timing().full_closing_flow_s;
  EXPECT_NEAR(predicted, (equilibrium_g - 1000.0) + 1000.0 * (let_through_kg - excess_kg), 1e-6);
  EXPECT_DOUBLE_EQ(p.growth_per_jiffy_g(), rate_g_per_jiffy);
  EXPECT_NEAR(p.impact_speed_m_s(), model::impact_speed(v0, model::kGravity<double>, config.orifice_to_floor_m), 1e-9);
}

// A heap that rises shortens the fall: the stream lands slower on what is already in the
// container; with `pile_rise 0` the fall stays the floor's.
TEST(FinalWeightPredictor, APileThatRisesShortensTheFall) {
  Config fixed;
  fixed.pile_grows = false;
  const Config rising;
  Predictor on_floor = started(fixed);
  Predictor on_pile = started(rising);
  on_floor.from_observer(20000.0, 24.0, 24.0);
  on_pile.from_observer(20000.0, 24.0, 24.0);
  const double v0 = model::outflow_speed(24.0 / (1000.0 * fixed.jiffy_s), on_floor.full_open_geometry().bore_area_m2,
                                         fixed.material.bulk_density);
  EXPECT_NEAR(on_floor.impact_speed_m_s(), model::impact_speed(v0, model::kGravity<double>, fixed.orifice_to_floor_m), 1e-9);
  EXPECT_LT(on_pile.impact_speed_m_s(), on_floor.impact_speed_m_s() - 0.1);
  EXPECT_LT(on_pile.fall_height_m(20000.0), rising.orifice_to_floor_m - 0.1);
  EXPECT_DOUBLE_EQ(on_pile.fall_height_m(0.0), rising.orifice_to_floor_m);
  // A narrower container: the same mass stands higher.
  Config narrow = rising;
  narrow.container_diameter_m = rising.container_diameter_m / 2.0;
  EXPECT_LT(started(narrow).fall_height_m(20000.0), on_pile.fall_height_m(20000.0));
}

// From the switch to half open, until the half-open stream is measured, the prediction grows at the
// half-open share of the flow measured before; the close from half open takes half a stroke less.
TEST(FinalWeightPredictor, TheFineFeedGrowsAtTheHalfOpenFlow) {
  const Config config;
  Predictor p = started(config);
  const double rate_g_per_jiffy = 24.0;
  const double predicted = p.from_observer(5000.0, rate_g_per_jiffy, rate_g_per_jiffy);
  const double settle_full_s = p.settle_delay_s();
  const DoseValveTiming<double> timing = datasheet_timing();

  p.switch_to_half(predicted, 300);
  EXPECT_TRUE(p.fine_feeding());
  EXPECT_NEAR(p.growth_per_jiffy_g(), rate_g_per_jiffy * timing.half_flow_ratio, 1e-12);
  EXPECT_NEAR(p.from_prior(310, kShape) - p.from_prior(300, kShape), 10.0 * rate_g_per_jiffy * timing.half_flow_ratio, 1e-9);
  EXPECT_NEAR(settle_full_s - p.settle_delay_s(), timing.stroke_s / 2.0, 1e-12);
  // The half-open stream reaches the pile a fall after the valve is at half.
  EXPECT_GT(p.half_stream_landing_s(), timing.half_transition_s + 0.2);
  // Less flow to let through from half open than from full: the prediction at the switch drops.
  EXPECT_LT(p.from_prior(300, kShape), predicted);
}

TEST(FinalWeightPredictor, TheLastGrainsFallFromRestAfterTheValveHasShut) {
  const Config config;
  const Predictor p = started(config);
  const DoseValveTiming<double> timing = datasheet_timing();
  EXPECT_NEAR(p.settle_delay_s(),
              timing.dead_s + timing.stroke_s + model::fall_time(0.0, model::kGravity<double>, config.orifice_to_floor_m), 1e-12);
}

}  // namespace
}  // namespace dynweigh::firmware
