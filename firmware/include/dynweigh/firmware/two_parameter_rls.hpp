#pragma once
// Recursive least squares for a law with two unknowns, y = theta1 x1 + theta2 x2, in float with a
// fixed 2 x 2 covariance: the pac baseline's spill law (x = Q, Q^2) and the baselines' close-before-
// the-flow-is-measured law (x = t, 1). Each fill is one observation. A forgetting factor lets the
// law follow a plant that drifts; the covariance's eigenvalues are held at or below the prior's larger
// variance so that fills which all excite the same direction (one target, one flow) cannot wind it up.
#include <cstdint>

namespace dynweigh::firmware {

class TwoParameterRls {
 public:
  // What a restart keeps (the settings' record). fills == 0: nothing learned yet.
  struct State {
    float theta1 = 0.0f;
    float theta2 = 0.0f;
    float p11 = 0.0f;
    float p12 = 0.0f;
    float p22 = 0.0f;
    std::uint16_t fills = 0;
  };

  // `forgetting` in (0, 1]; `noise` the standard deviation of one observation of y.
  void configure(float forgetting, float noise);
  // The prior: theta and the standard deviation of each (uncorrelated); also the covariance's bound.
  void reset(float theta1, float theta2, float sd1, float sd2);
  // A learned state replaces the prior (the prior's trace bound stays); false if it is not a sane
  // one (not finite, covariance not positive definite), the prior then stays.
  bool restore(const State& state);
  static bool sane(const State& state);

  float predict(float x1, float x2) const { return state_.theta1 * x1 + state_.theta2 * x2; }
  // One observation; ignored (false) if it is not finite.
  bool update(float x1, float x2, float y);
  const State& state() const { return state_; }

 private:
  void limit_eigenvalues(State& s) const;
  State state_;
  float forgetting_ = 1.0f;
  float noise_variance_ = 1.0f;
  float max_eigenvalue_ = 0.0f;
};

}  // namespace dynweigh::firmware
