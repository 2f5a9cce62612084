#pragma once
// What the model strategy's certified fills of one material measured, kept with that material in the
// settings record so that it survives a restart and reaches the next dose. Two lessons:
// - the open-time law, final = theta1 t + theta2 with t the valve's open time (command to command):
//   theta1 is the material's full flow through this bore in g/s, theta2 what the valve's dead time,
//   the flow's start-up and the let-through at the close add to it. Every fill closed from full open
//   is a point on it; a fill that closes before its stream can be weighed is timed by it, up to a
//   reach beyond the longest open time it was taught at (docs/strategies.md).
// - the measured close's let-through: what the valve let through after the close command, in seconds
//   of the flow at the close, as the measured closes' finals showed it (the timing in use's
//   let-through plus what the final came out above the model's prediction). It holds whatever
//   the valve's timing in use is, datasheet or learned.
// With them, the valve's timing as the doses of this material measured it (valve_timing_learning.hpp),
// the last few doses that ran full open, which tell how the fill grows with the open time where
// the law's line does not (dose_history.hpp), and how far its measured closes came out from their
// predictions against the uncertainty the plan gave them (measured_close_spread.hpp).
#include <cstdint>

#include "dynweigh/firmware/dose_history.hpp"
#include "dynweigh/firmware/measured_close_spread.hpp"
#include "dynweigh/firmware/two_parameter_rls.hpp"
#include "dynweigh/firmware/valve_timing_learning.hpp"

namespace dynweigh::firmware {

struct MaterialLearning {
  TwoParameterRls::State open_time_law{};  // fills == 0: nothing learned
  float close_let_through_s = 0.0f;
  std::uint16_t residual_fills = 0;
  float law_longest_open_s = 0.0f;  // the longest open time the law was taught at (0: none known)
  ValveTimingLearning valve{};
  DoseHistory doses{};
  MeasuredCloseSpread measured_closes{};
  bool empty() const {
    return open_time_law.fills == 0 && residual_fills == 0 && valve.empty() && doses.size() == 0 &&
           measured_closes.closes() == 0;
  }
};

}  // namespace dynweigh::firmware
