#pragma once
// Dynamic weighing: the final static weight from the platform's free, damped ringing, long before
// the ringing has died away. After the last grain has landed the reading is W plus a damped
// sinusoid, which obeys y[n] - W = c1 (y[n-1] - W) + c2 (y[n-2] - W) exactly (Prony). So
// y[n] = c1 y[n-1] + c2 y[n-2] + d is linear in (c1, c2, d), solved by least squares over a
// window, and W = d / (1 - c1 - c2). The fit's covariance gives W's standard error: the result is
// certified when that error is small, not when a filter has settled.
#include <Eigen/Dense>
#include <cmath>
#include <cstddef>

namespace dynweigh::model {

template <typename Scalar, std::size_t Capacity>
class DampedSettlingFit {
 public:
  static_assert(Capacity >= 8, "a damped sinusoid needs a few periods of samples");
  static constexpr std::size_t kMinimumSamples = 12;

  void reset() { count_ = 0; head_ = 0; }
  void push(Scalar value) {
    samples_[head_] = value;
    head_ = (head_ + 1) % Capacity;
    if (count_ < Capacity) ++count_;
  }
  std::size_t count() const { return count_; }

  struct Estimate {
    bool valid = false;
    Scalar final_value = 0;     // W
    Scalar standard_error = 0;  // of W, from the residuals
    Scalar residual_rms = 0;
  };

  Estimate fit() const {
    Estimate e;
    if (count_ < kMinimumSamples) return e;
    // Relative to the newest sample: W is near it, so float keeps its resolution at full scale.
    const Scalar reference = at(count_ - 1);
    Eigen::Matrix<Scalar, 3, 3> normal = Eigen::Matrix<Scalar, 3, 3>::Zero();
    Eigen::Matrix<Scalar, 3, 1> rhs = Eigen::Matrix<Scalar, 3, 1>::Zero();
    for (std::size_t n = 2; n < count_; ++n) {
      const Eigen::Matrix<Scalar, 3, 1> row(at(n - 1) - reference, at(n - 2) - reference, Scalar(1));
      const Scalar y = at(n) - reference;
      normal.noalias() += row * row.transpose();
      rhs.noalias() += row * y;
    }
    const Eigen::LDLT<Eigen::Matrix<Scalar, 3, 3>> solver(normal);
    if (solver.info() != Eigen::Success) return e;
    const Eigen::Matrix<Scalar, 3, 1> c = solver.solve(rhs);
    const Scalar loop_gain = Scalar(1) - c(0) - c(1);
    if (!(std::fabs(loop_gain) > Scalar(1e-4))) return e;  // no decay: W is not identifiable yet
    Scalar residual_sum = 0;
    for (std::size_t n = 2; n < count_; ++n) {
      const Scalar r = at(n) - reference - c(0) * (at(n - 1) - reference) - c(1) * (at(n - 2) - reference) - c(2);
      residual_sum += r * r;
    }
    const Scalar dof = Scalar(count_ - 2) - Scalar(3);
    const Scalar variance = residual_sum / dof;
    const Scalar w = c(2) / loop_gain;
    // First-order propagation of the parameters' covariance into W = d / (1 - c1 - c2).
    const Eigen::Matrix<Scalar, 3, 1> gradient(w / loop_gain, w / loop_gain, Scalar(1) / loop_gain);
    const Eigen::Matrix<Scalar, 3, 1> inverse_times_gradient = solver.solve(gradient);
    const Scalar w_variance = variance * gradient.dot(inverse_times_gradient);
    e.valid = std::isfinite(w) && w_variance >= Scalar(0);
    e.final_value = reference + w;
    e.standard_error = std::sqrt(std::fmax(w_variance, Scalar(0)));
    e.residual_rms = std::sqrt(variance);
    return e;
  }

 private:
  Scalar at(std::size_t i) const {  // i = 0 is the oldest kept
    return samples_[(head_ + Capacity - count_ + i) % Capacity];
  }
  Scalar samples_[Capacity] = {};
  std::size_t count_ = 0;
  std::size_t head_ = 0;
};

}  // namespace dynweigh::model
