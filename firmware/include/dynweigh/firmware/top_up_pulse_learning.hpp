#pragma once
// What the top-up pulses of one material taught, kept with that material in the settings record so
// that the next dose's first pulse is sized by it, across a restart too: for full-open and for
// half-open pulses, the law (m = q e - c, top_up_pulse_law.hpp: q, c and how sure of them it is),
// the prior it was learned against (the flow and the valve's travel) and how many pulses taught it.
#include <cstdint>

#include "dynweigh/firmware/two_parameter_rls.hpp"

namespace dynweigh::firmware {

struct PulseLawLearning {
  TwoParameterRls::State law{};  // theta1 q, theta2 c
  float prior_flow_g_s = 0.0f;  // the dose's flow the law started from: its bounds
  float travel_s = 0.0f;        // the valve's travel to this opening, as the pulses taught it
  std::uint8_t pulses = 0;      // 0: nothing learned
};

struct TopUpPulseLearning {
  PulseLawLearning full{};
  PulseLawLearning half{};
  bool empty() const { return full.pulses == 0 && half.pulses == 0; }
};

}  // namespace dynweigh::firmware
