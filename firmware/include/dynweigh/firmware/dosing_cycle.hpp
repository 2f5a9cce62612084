#pragma once
// One dose, from `dose` to its certified result: the valve opens, the strategy decides the cutoff,
// the scale settles, the stable weight is the result. A fault aborts it with the valve closed.
#include <cstdint>

#include "dynweigh/firmware/dosing_strategy.hpp"
#include "dynweigh/firmware/io.hpp"
#include "dynweigh/firmware/model_cutoff.hpp"
#include "dynweigh/firmware/parameters.hpp"
#include "dynweigh/firmware/stable_weight_detector.hpp"

namespace dynweigh::firmware {

struct DoseResult {
  std::int32_t target_g = 0;
  std::int32_t final_g = 0;
  std::uint32_t time_ms = 0;
  std::uint32_t cutoff_jiffy = 0;  // jiffies from `dose` to the close command
  DosingStrategy strategy = DosingStrategy::model;
};

class DosingCycle {
 public:
  enum class Phase : std::uint8_t { idle, dosing, settling };
  enum class Outcome : std::uint8_t { running, certified, timed_out, never_stable };

  void configure(const Parameters& parameters);
  void start(std::int32_t target_g, DosingStrategy strategy, float start_weight_g);
  // One jiffy with the unfiltered and the filtered net weight (grams).
  Outcome step(float net_weight_g, float filtered_weight_g);
  void abort() { phase_ = Phase::idle; valve_ = ValveCommand::closed; }

  Phase phase() const { return phase_; }
  ValveCommand valve() const { return valve_; }
  // Fraction of the coming jiffy after which the close should act (0 = at once).
  float close_delay_fraction() const { return close_delay_fraction_; }
  float last_prediction_g() const { return last_prediction_g_; }
  const DoseResult& result() const { return result_; }

 private:
  bool should_close(float net_weight_g, float filtered_weight_g);

  ModelCutoff model_;
  StableWeightDetector stable_;
  float jiffy_s_ = 0.01f;
  float preact_g_ = 0.0f;
  float timeout_s_ = 120.0f;
  float settle_limit_s_ = 60.0f;

  Phase phase_ = Phase::idle;
  ValveCommand valve_ = ValveCommand::closed;
  DoseResult result_;
  float start_weight_g_ = 0.0f;
  float last_prediction_g_ = 0.0f;
  float close_delay_fraction_ = 0.0f;
  std::uint32_t jiffies_ = 0;
  std::uint32_t settle_from_jiffy_ = 0;
};

}  // namespace dynweigh::firmware
