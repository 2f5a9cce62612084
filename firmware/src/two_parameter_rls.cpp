#include "dynweigh/firmware/two_parameter_rls.hpp"

#include <cmath>

namespace dynweigh::firmware {
namespace {
constexpr float kRegularisation = 1e-4f;
}  // namespace

// Forgetting lets the variance grow without bound in a direction no fill excites (every fill at one
// flow). Each eigenvalue of P is held at or below the prior's larger variance: the unexcited direction
// is then no less certain than the prior, and the excited one keeps its own, small, variance (a bound
// on the trace instead would shrink that one too, and the law would stop following the plant).
void TwoParameterRls::limit_eigenvalues(State& s) const {
  const float mean = 0.5f * (s.p11 + s.p22);
  const float half_gap = 0.5f * (s.p11 - s.p22);
  const float radius = std::sqrt(half_gap * half_gap + s.p12 * s.p12);
  const float larger = mean + radius;
  if (!(larger > max_eigenvalue_)) return;
  const float smaller = mean - radius;
  if (smaller >= max_eigenvalue_ || !(radius > 0.0f)) {
    s.p11 = s.p22 = max_eigenvalue_;
    s.p12 = 0.0f;
    return;
  }
  // The larger eigenvalue's unit eigenvector v: P -= (larger - bound) v v^T.
  float v1 = s.p12, v2 = larger - s.p11;
  if (std::fabs(v2) < std::fabs(larger - s.p22)) {  // the better conditioned of the two forms
    v1 = larger - s.p22;
    v2 = s.p12;
  }
  const float norm = std::sqrt(v1 * v1 + v2 * v2);
  v1 /= norm;
  v2 /= norm;
  const float excess = larger - max_eigenvalue_;
  s.p11 -= excess * v1 * v1;
  s.p12 -= excess * v1 * v2;
  s.p22 -= excess * v2 * v2;
}

void TwoParameterRls::configure(float forgetting, float noise) {
  forgetting_ = forgetting > 0.0f && forgetting <= 1.0f ? forgetting : 1.0f;
  noise_variance_ = noise > 0.0f ? noise * noise : 1.0f;
}

void TwoParameterRls::reset(float theta1, float theta2, float sd1, float sd2) {
  state_ = State{theta1, theta2, sd1 * sd1, 0.0f, sd2 * sd2, 0};
  max_eigenvalue_ = state_.p11 > state_.p22 ? state_.p11 : state_.p22;
}

bool TwoParameterRls::sane(const State& s) {
  const bool finite = std::isfinite(s.theta1) && std::isfinite(s.theta2) && std::isfinite(s.p11) &&
                      std::isfinite(s.p12) && std::isfinite(s.p22);
  return finite && s.p11 > 0.0f && s.p22 > 0.0f && s.p11 * s.p22 > s.p12 * s.p12;
}

bool TwoParameterRls::restore(const State& state) {
  if (!sane(state)) return false;
  state_ = state;
  return true;
}

bool TwoParameterRls::update(float x1, float x2, float y) {
  if (!std::isfinite(x1) || !std::isfinite(x2) || !std::isfinite(y)) return false;
  State s = state_;
  // P phi and the innovation's variance.
  const float px1 = s.p11 * x1 + s.p12 * x2;
  const float px2 = s.p12 * x1 + s.p22 * x2;
  const float innovation_variance = forgetting_ * noise_variance_ + x1 * px1 + x2 * px2;
  if (!(innovation_variance > 0.0f)) return false;
  const float g1 = px1 / innovation_variance;
  const float g2 = px2 / innovation_variance;
  const float residual = y - (s.theta1 * x1 + s.theta2 * x2);
  s.theta1 += g1 * residual;
  s.theta2 += g2 * residual;
  // P = (P - g (P phi)^T) / lambda, kept symmetric.
  s.p11 = (s.p11 - g1 * px1) / forgetting_;
  s.p12 = (s.p12 - g1 * px2) / forgetting_;
  s.p22 = (s.p22 - g2 * px2) / forgetting_;
  limit_eigenvalues(s);
  if (!sane(s) && max_eigenvalue_ > 0.0f) {
    // Many fills along one direction leave P nearly singular; rounding may tip it over. A little
    // uncertainty back on the diagonal keeps it a covariance.
    s.p11 += kRegularisation * max_eigenvalue_;
    s.p22 += kRegularisation * max_eigenvalue_;
  }
  if (!sane(s)) return false;  // keep the last state
  if (s.fills < 0xFFFF) ++s.fills;
  state_ = s;
  return true;
}

}  // namespace dynweigh::firmware
