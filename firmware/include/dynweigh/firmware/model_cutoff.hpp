#pragma once
// The `model` strategy's view of a fill, in three parts: the valve's timing and what the scale has
// learned of it (learned_valve_timing.hpp), what the dose's samples tell of the stream
// (dose_estimator.hpp), and the final weight predicted from both (final_weight_predictor.hpp).
// Before the stream is measured the prediction comes from the open-time law this material's earlier
// fills taught (learned_fill_law.hpp), or before any, from the configured geometry and the valve's
// timing. A measured close adds the residual the earlier measured closes left.
#include <cstdint>

#include "dynweigh/firmware/dose_estimator.hpp"
#include "dynweigh/firmware/final_weight_predictor.hpp"
#include "dynweigh/firmware/learned_fill_law.hpp"
#include "dynweigh/firmware/learned_valve_timing.hpp"
#include "dynweigh/firmware/parameters.hpp"

namespace dynweigh::firmware {

// Scalar is float on the target; the double instantiation is the reference the numerical stress
// tests run beside it.
template <typename Scalar>
class BasicModelCutoff {
 public:
  void configure(const Parameters& parameters);
  // What earlier fills of the material about to be dosed taught (nothing learned: the prior).
  void restore(const MaterialLearning& learned) {
    law_.restore(learned);
    valve_.restore(learned.valve);
  }
  // What this material's fills have taught so far, the valve's timing with it.
  MaterialLearning learned() const {
    MaterialLearning l = law_.learned();
    l.valve = valve_.learned();
    return l;
  }
  // Called at the jiffy the valve is commanded open; weights are net grams on the scale. The target
  // tells where the doses the material kept are fitted (dose_history.hpp); 0: nowhere.
  void start(Scalar start_weight_g, Scalar target_g = Scalar(0));
  // One unfiltered sample per jiffy; returns the predicted final fill (grams added by this dose)
  // if the valve were commanded closed now.
  Scalar observe(Scalar net_weight_g);
  // Grams the fill grows per jiffy at the present flow, for timing the close within the jiffy.
  Scalar growth_per_jiffy_g() const;
  // How far into the coming jiffy a close may come at the earliest: never before the valve has
  // opened a quarter of its stroke (a fill closed sooner delivers next to nothing and teaches
  // nothing). Above 1: not in the coming jiffy.
  Scalar earliest_close_fraction() const;
  // The open-time law times this close, and the coming jiffy takes the open time further beyond
  // the longest the law was taught at than the law can be trusted to reach.
  bool beyond_the_law() const;
  // The close was commanded `fraction` of a jiffy after the last observed sample.
  void closed(Scalar fraction);
  // The dose closed by closed() was certified at `final_g`: what it teaches this material.
  // `close_sigma_g`: the uncertainty the plan gave a measured close, before its scale (0: none).
  void learn(Scalar final_g, float close_sigma_g = 0.0f);
  const LearnedFillLaw& fill_law() const { return law_; }
  // Seconds from the close command until the last grain has landed.
  Scalar settle_delay_s() const { return predictor_.settle_delay_s(); }
  bool measuring() const { return estimator_.measuring(); }
  Scalar measured_flow_kg_s() const;
  // Orifice to pile top once `net_weight_g` is on the scale (the learning table's key).
  Scalar fall_height_m(Scalar net_weight_g) const { return predictor_.fall_height_m(net_weight_g); }

  // The valve goes to half: the flow, the open area and the let-through change, so the flow is
  // measured again once the half-open stream has reached the pile. Until then the prediction at the
  // switch grows at the half-open flow Beverloo gives.
  void switch_to_half(Scalar predicted_now_g);
  bool fine_feeding() const { return predictor_.fine_feeding(); }
  const DoseEstimates<Scalar>& estimates() const { return estimator_.estimates(); }
  // The valve dead time the prediction uses: the datasheet's, or the measured one once it differs.
  Scalar dead_time_in_use_s_now() const { return valve_.in_use().dead_s; }
  // What the valve's feedback showed: the mean time from the command to the end position (closing
  // if seen, else opening) over `strokes` full strokes. The next dose's stroke is that less the dead
  // time in use, once it is clearly off the datasheet's.
  void measured_valve_travel(Scalar mean_s, std::uint32_t strokes) { valve_.measured_travel(mean_s, strokes); }
  Scalar stroke_in_use_s_now() const { return valve_.in_use().stroke_s; }
  // The stroke as the feedback has timed it up to now, this dose's strokes included (the dose itself
  // keeps the one in use at its start).
  Scalar stroke_timed_s() const { return valve_.stroke_in_use_s(valve_.in_use().dead_s); }
  Scalar half_flow_ratio() const { return valve_.in_use().half_flow_ratio; }
  const model::GateFlowShape<Scalar>& gate_flow_shape() const { return valve_.gate_flow_shape(); }

 private:
  // From the open command to the newest sample: the sample of the n-th jiffy shows n - 1 jiffies
  // of the valve's being open.
  Scalar open_s() const { return Scalar(estimator_.jiffies() - 1) * jiffy_s_; }

  Scalar jiffy_s_ = Scalar(0.01);
  BasicLearnedValveTiming<Scalar> valve_;
  BasicDoseEstimator<Scalar> estimator_;
  BasicFinalWeightPredictor<Scalar> predictor_;
  LearnedFillLaw law_;
  bool timed_by_law_ = false;  // the last prediction came from the open-time law
  static constexpr std::uint32_t kCurveFitJiffy = 2;
  Scalar target_open_s_ = Scalar(0);     // the open time the law's line gives for the target
  DoseHistory::PowerLaw near_target_{};  // the kept doses' curve near it
  bool curve_fitted_ = false;
  bool timed_by_curve_ = false;  // ... and the curve, above the law's line, gave it
  Scalar model_prediction_g_ = Scalar(0);  // the last, before the learn strategy's correction
  CloseRecord close_{};
};

using ModelCutoff = BasicModelCutoff<float>;

extern template class BasicModelCutoff<float>;
extern template class BasicModelCutoff<double>;

}  // namespace dynweigh::firmware
