#pragma once
// One dose, from `dose` to its certified result: the valve opens, the strategy decides the cutoff
// (timed within the jiffy for the model), the scale settles, and the result is certified either
// dynamically (a fit of the platform's damped ringing) or as industrial indicators do (stable
// weight). A fault aborts it with the valve closed. The valve opens only from a scale at rest: a
// start weight taken while the scale moves would be wrong by the motion, and so would the fill.
#include <cstdint>

#include "dynweigh/firmware/baseline_learning.hpp"
#include "dynweigh/firmware/dose_plan.hpp"
#include "dynweigh/firmware/dosing_strategy.hpp"
#include "dynweigh/firmware/fault.hpp"
#include "dynweigh/firmware/flow_preact_cutoff.hpp"
#include "dynweigh/firmware/io.hpp"
#include "dynweigh/firmware/learning_table.hpp"
#include "dynweigh/firmware/model_cutoff.hpp"
#include "dynweigh/firmware/pac_cutoff.hpp"
#include "dynweigh/firmware/parameters.hpp"
#include "dynweigh/firmware/pulse_verdict.hpp"
#include "dynweigh/firmware/rest_noise.hpp"
#include "dynweigh/firmware/sizing_reading.hpp"
#include "dynweigh/firmware/stable_weight_detector.hpp"
#include "dynweigh/firmware/top_up_pulse_law.hpp"
#include "dynweigh/firmware/two_stage_cutoff.hpp"
#include "dynweigh/model/damped_settling_fit.hpp"

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
  enum class Phase : std::uint8_t { idle, dosing, settling, pulsing };
  // `nothing_delivered`: whatever the strategy, a dose whose certified fill is no more than its own
  // OIML R61 X(5) limit (5 x the X(1) initial-verification deviation for its target) and no more
  // than a fifth of what the strategy predicted at its close delivered nothing a filling line can
  // use: a silo run empty, a valve that let nothing through, while a strategy closed on its prior.
  // It ends in a fault, never in a result; unless the valve never had the time to open
  // (valve_could_deliver; its feedback still reading `moving` at the close): then the strategy
  // closed too soon and the plant is sound, and its top-up finds out (dose_delivered_nothing). A
  // close meant to end far short (the model's, at the reach of what earlier fills taught it, on a
  // slow valve whose first tenths of a second let little through) delivers a good share of what it
  // predicted: a top-up finishes it.
  // `reading_frozen`: the reading did not move once while the grains in flight at the close, or at
  // the end of a pulse that reached its position, landed (watch_for_frozen_reading). Landing grains
  // move any live load cell's reading; a hung converter's result would be what it last read.
  enum class Outcome : std::uint8_t { running, certified, timed_out, never_stable, nothing_delivered, reading_frozen };
  static constexpr float kNothingDeliveredClass = 5.0f;
  static constexpr float kNothingDeliveredShare = 0.2f;

  void configure(const Parameters& parameters);
  // Every jiffy, dosing or not: whether the scale is at rest, at what weight, and with what noise on
  // the unfiltered net weight; `counts_per_gram` the span in use (0: not calibrated).
  void watch_standstill(float filtered_weight_g, float net_weight_g, float counts_per_gram);
  // `learning` (the learn strategy's corrections) must outlive the dose; may be null otherwise.
  // The valve opens in the first step() whose sample finds the scale at rest (time counts from here).
  void start(std::int32_t target_g, DosingStrategy strategy, const LearningTable* learning = nullptr);
  // One jiffy with the unfiltered and the filtered net weight (grams); `fresh` is false when the
  // jiffy brought no sample (the weights are the last ones held).
  Outcome step(float net_weight_g, float filtered_weight_g, bool fresh = true);
  void abort() { phase_ = Phase::idle; valve_ = ValveCommand::closed; }

  // A top-up of the certified result, `deficit_g` short of the target: one valve pulse, then the
  // dose settles and is certified again as it was the first time (step() returns `certified`; the
  // result's final and time then include the pulse, its cutoff stays the first close's). The pulse
  // is sized from the flow the dose measured (top_up_pulse_law.hpp), at most `fixed_pulse_s`; a
  // strategy that measured no flow pulses `fixed_pulse_s` full open. `pulses_after`: how many more
  // the dose may give (0: this is the last); `accepted_short_g`: how far short a fill may end
  // without another (0: not told, and the pulse before the last aims for the class alone).
  void start_top_up(float deficit_g, float fixed_pulse_s, std::uint8_t pulses_after = 255,
                    float accepted_short_g = 0.0f);
  // After the top-up's certified result: what the pulse delivered; false if the scale saw (about)
  // nothing of it (a frozen reading, an empty silo): no further pulse is sized on that.
  bool learn_top_up(float delivered_g);
  // Whether the scale saw (about) nothing of the last pulse, `delivered_g` being what it saw.
  bool pulse_moved_nothing(float delivered_g) const;
  // While a top-up may follow the coming close or pulse, the tolerance's bands below the target:
  // `warn_low_g` (TL1), from which the model's own top-up tells how short it accepts a fill, and
  // `reject_low_g` (TL2) where `tol_action topup` tops up another strategy's fill (0: it does not).
  // A dynamically certified reading short by clearly more than that then only sizes the next
  // pulse, and is taken as soon as it is good enough for that (sizing_reading.hpp). Both 0: every
  // reading is certified in full. start() and start_top_up() set both 0.
  void allow_sizing_reading(float warn_low_g, float reject_low_g) {
    sizing_warn_low_g_ = warn_low_g > 0.0f ? warn_low_g : 0.0f;
    sizing_reject_low_g_ = reject_low_g > 0.0f ? reject_low_g : 0.0f;
  }
  // The last `certified` outcome was such a reading: it sizes a pulse and is never reported.
  bool reading_sizes_only() const { return reading_sizes_only_; }
  // The pulse that reading was to size will not come: the dose settles on, the fit's window kept,
  // until the reading is certified in full (step() returns `certified` again).
  void certify_in_full();
  // The whole dose, its close and its pulses, brought no more than its X(5) limit: after a pulse
  // whose feedback showed the valve open or at half and that the scale saw nothing of, a silo that
  // delivers nothing, found after a close the valve was too slow for.
  bool dose_delivered_nothing() const;
  bool sizes_top_ups() const { return top_up_flow_g_s_ > 0.0f; }
  // The unfiltered reading did not move once while the grains in flight at the close (or at a
  // pulse's end) landed, or stood still for kFrozenSamples samples while the fill settled: no pulse
  // may be sized or judged on such a reading.
  bool reading_frozen() const { return frozen_reading_; }
  static constexpr std::uint32_t kFrozenSamples = 30;
  const TopUpPulseLaw::Pulse& last_pulse() const { return pulse_; }
  // The model's plan at its close (a baseline's: twostage's coarse-and-fine is `fine`, the others
  // close from full flow), and the flow's fluctuation it saw.
  PlanChoice plan() const;
  float flow_fluctuation() const { return planner_.fluctuation(); }

  Phase phase() const { return phase_; }
  ValveCommand valve() const { return valve_; }
  // For the valve module's delay byte: how far into the coming jiffy the command should act.
  std::uint8_t valve_delay_100us() const { return valve_delay_100us_; }
  float last_prediction_g() const { return last_prediction_g_; }
  const DoseResult& result() const { return result_; }
  // The standstill weight the dose started from (a top-up measures its final from it too).
  float start_weight_g() const { return start_weight_g_; }
  // After a certified twostage fill: its fine preact and coarse time, adapted.
  const TwoStageCutoff& two_stage() const { return two_stage_; }
  // What the pac and flowpreact baselines learned: restored before a dose, read after its result.
  void restore_baselines(const BaselineLearning& learned) {
    pac_.restore(learned.pac);
    flow_preact_.restore(learned.flowpreact);
  }
  const PacCutoff& pac() const { return pac_; }
  const FlowPreactCutoff& flow_preact() const { return flow_preact_; }
  // The kind of fill the learn strategy closed: where its residual belongs.
  const LearningKey& learning_key() const { return learning_key_; }
  // What the model's earlier fills and top-up pulses of the material about to be dosed taught:
  // restored before a dose; after a certified model or learn result or a sized pulse, what it adds
  // (the material's to keep).
  void restore_material(const MaterialLearning& learned, const TopUpPulseLearning& pulses) {
    model_.restore(learned);
    top_up_law_.restore(pulses);
  }
  TopUpPulseLearning top_up_learning() const { return top_up_law_.learned(); }
  const LearnedFillLaw& model_fill_law() const { return model_.fill_law(); }
  // What the selected material's model or learn fills taught, to keep with it.
  MaterialLearning model_learned() const { return model_.learned(); }
  // What the last model or learn dose measured of the valve and the material.
  const DoseEstimates<float>& model_estimates() const { return model_.estimates(); }
  float model_dead_time_s() const { return model_.dead_time_in_use_s_now(); }
  float model_stroke_s() const { return model_.stroke_in_use_s_now(); }
  // What the valve's feedback has shown of its timing; the model's next dose times its close with it.
  void measured_valve_travel(float mean_s, std::uint32_t strokes) { model_.measured_valve_travel(mean_s, strokes); }
  // How long the valve's feedback showed it moving from closed to half (0: never timed); the top-up's
  // half-open pulses are sized with it from the next pulse on.
  void measured_half_travel(float motion_s) { half_travel_s_ = motion_s; }
  // Whether the valve was open long enough to deliver (the fault supervisor's judgement, each
  // jiffy): a dose closed before its valve opened is no `nothing_delivered`, only a poor fill.
  void valve_could_deliver(bool could) { valve_could_deliver_ = could; }

 private:
  void open_from_rest();
  bool decide_model(float net_weight_g);
  bool decide_preact(float filtered_weight_g, float preact_g);
  bool decide_twostage(float filtered_weight_g);
  bool decide_flow_baseline(float filtered_weight_g);
  void close_valve(float settle_delay_s);
  bool certify(float net_weight_g, float filtered_weight_g);
  bool sizes_next_pulse(const RecentEstimates& recent, float standard_error_g, float final_value) const;
  void learn_from_close();
  void forget_sizing_reading();  // every reading certified in full until allow_sizing_reading()
  PulseVerdict last_pulse_verdict(float delivered_g) const;
  float pulse_travel_s() const;  // the valve's travel to the position the pulse was sent to
  bool settling_fit_describes_reading(float residual_rms_g);
  bool certify_dynamically() const;
  bool delivered_nothing() const;
  float nothing_delivered_limit_g() const;  // kNothingDeliveredClass x the target's X(1) limit
  void keep_top_up_flow();
  float plan_step(float growth_g_per_jiffy);
  float fine_lead_s() const;
  // True in the jiffy it finds that the reading did not move while grains in flight landed.
  bool watch_for_frozen_reading(float net_weight_g, bool fresh);
  Outcome step_pulse();

  ModelCutoff model_;
  TwoStageCutoff two_stage_;
  PacCutoff pac_;
  FlowPreactCutoff flow_preact_;
  StableWeightDetector stable_;
  StableWeightDetector standstill_;
  RestNoise rest_noise_;
  float noise_span_ = 0.0f;    // the span rest_noise_ was measured under
  float rest_noise_g_ = 0.0f;  // the scale's noise at rest when the dose opened (rest_noise.hpp)
  model::DampedSettlingFit<float, 64> settling_fit_;
  float jiffy_s_ = 0.01f;
  float preact_g_ = 0.0f;
  float model_fine_s_ = 0.0f;
  bool fine_point_passed_ = false;  // this dose's fine feed would have begun by now: no longer a plan
  float timeout_s_ = 120.0f;
  float settle_limit_s_ = 60.0f;
  bool subjiffy_ = true;
  CertifyMode certify_mode_ = CertifyMode::automatic;

  Phase phase_ = Phase::idle;
  bool awaiting_rest_ = false;
  ValveCommand valve_ = ValveCommand::closed;
  std::uint8_t valve_delay_100us_ = 0;
  DoseResult result_;
  const LearningTable* learning_ = nullptr;
  LearningKey learning_key_;
  float start_weight_g_ = 0.0f;
  bool valve_could_deliver_ = true;
  float last_prediction_g_ = 0.0f;
  float half_travel_s_ = 0.0f;
  std::uint32_t jiffies_ = 0;
  std::uint32_t settle_from_jiffy_ = 0;
  static constexpr std::uint32_t kAgreementJiffies = 5;
  float recent_estimates_[kAgreementJiffies] = {};
  std::uint32_t estimates_ = 0;
  std::uint32_t blind_jiffies_ = 0;
  std::uint32_t blind_horizon_jiffies_ = 10;  // the stale-sample limit: blind this long, a dose faults

  DosePlanner planner_;
  PlanChoice plan_;
  float close_sigma_g_ = 0.0f;  // the plan's uncertainty for a measured close now, before its scale
  float measured_sigma_scale_ = 1.0f;  // what the material's measured closes showed of it
  float sizing_warn_low_g_ = 0.0f;     // allow_sizing_reading()
  float sizing_reject_low_g_ = 0.0f;
  bool reading_sizes_only_ = false;
  bool close_taught_ = false;  // the strategy learned from this dose's close (once, however certified)
  TopUpPulseLaw top_up_law_;
  TopUpPulseLaw::Pulse pulse_;
  float top_up_flow_g_s_ = 0.0f;  // full open, as measured at the close (0: none measured)
  bool topping_up_ = false;
  std::uint32_t pulse_end_jiffy_ = 0;
  std::uint32_t closed_jiffy_ = 0;
  float last_net_g_ = 0.0f;
  bool frozen_reading_ = false;
  bool grains_in_flight_ = false;      // the close, or a pulse that reached its position
  bool moved_since_close_ = false;
  std::uint32_t still_samples_ = 0;
  std::uint32_t open_jiffy_ = 0;
  float dose_open_s_ = 0.0f;  // the dose as one full-open pulse (0: it was not one)
};

}  // namespace dynweigh::firmware
