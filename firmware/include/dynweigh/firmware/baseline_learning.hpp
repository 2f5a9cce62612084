#pragma once
// What the pac and flowpreact baselines learned over their fills, kept in the settings' record so a
// restart does not forget it. A part with fills == 0 is unlearned: the strategy starts from the
// priors it derives from the installation parameters.
#include <cstdint>

#include "dynweigh/firmware/two_parameter_rls.hpp"

namespace dynweigh::firmware {

struct PacLearned {
  TwoParameterRls::State spill;  // spill (g) = theta1 Q + theta2 Q^2, Q the flow at the close in kg/s
  TwoParameterRls::State blind;  // fill (g) = theta1 t + theta2, closed t s after the open, unmeasured
};

struct FlowPreactLearned {
  float lag_s = 0.0f;  // preact (g) = the flow at the close x lag
  std::uint16_t fills = 0;
  TwoParameterRls::State blind;
};

struct BaselineLearning {
  PacLearned pac;
  FlowPreactLearned flowpreact;
};

}  // namespace dynweigh::firmware
