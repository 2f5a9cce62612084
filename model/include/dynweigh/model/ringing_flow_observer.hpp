#pragma once
// The static mass and the landing flow seen through the platform's ringing, without a low-pass
// filter's lag. The scale is a lightly damped spring: its reading y follows the force (as grams)
// W through y'' + 2 zeta w y' + w^2 y = w^2 W. During a dose W = S + k L: the static mass S grows
// at the landing rate L, and the stream's momentum flux adds L v / g (k = v / g in jiffies). L
// wanders with the silo's flow, and each jiffy's landing scatters around it; through k that
// scatter shakes the force by tens of grams, so the platform never stops ringing. A Kalman filter
// whose state holds S, L, the reading y and its rate u separates the three: S and L at the newest
// sample, the ringing y - W apart.
//
// Time runs in jiffies (one sample each), weights in grams relative to the first sample, so float
// keeps its resolution at full scale. The platform's frequency falls as the scale fills; the caller
// passes it each jiffy and the transition is recomputed when it has moved.
#include <Eigen/Dense>
#include <cmath>

namespace dynweigh::model {

template <typename Scalar>
class RingingFlowObserver {
 public:
  using Vector = Eigen::Matrix<Scalar, 4, 1>;
  using Matrix = Eigen::Matrix<Scalar, 4, 4>;
  enum Index { kStatic = 0, kRate = 1, kReading = 2, kReadingRate = 3 };

  struct Tuning {
    Scalar rate_walk_g = Scalar(0.3);      // rms change of the mean landing rate per jiffy, g/jiffy
    Scalar landing_scatter_g = Scalar(1.7);  // rms of one jiffy's landing about the mean, g
    Scalar sample_noise_g = Scalar(0.5);   // load-cell noise and the 1 d rounding
    Scalar outlier_sigmas = Scalar(6);     // a sample this far from the prediction is not believed
    int outliers_before_accepting = 3;     // ... unless that many in a row: the signal has moved
  };

  void set_tuning(const Tuning& tuning) { tuning_ = tuning; }
  const Tuning& tuning() const { return tuning_; }

  // Angular frequency in radians per jiffy (2 pi f T) and damping ratio of the platform now, and
  // the impact's lag k = v / g in jiffies (the force per landing rate). The load cell carries the
  // platform's whole support, the spring's force and the damper's: it reads y + (2 zeta / w) u.
  void set_platform(Scalar omega_per_jiffy, Scalar damping_ratio, Scalar impulse_jiffies) {
    const auto moved = [](Scalar now, Scalar before) { return std::fabs(now - before) > Scalar(0.002) * before; };
    if (!moved(omega_per_jiffy, omega_) && !moved(impulse_jiffies, impulse_jiffies_) && damping_ratio == zeta_) {
      return;
    }
    omega_ = omega_per_jiffy;
    zeta_ = damping_ratio;
    impulse_jiffies_ = impulse_jiffies;
    transition_ = discretize(omega_, zeta_, impulse_jiffies_);
    reads_.setZero();
    reads_(kReading) = Scalar(1);
    if (omega_ > Scalar(0)) reads_(kReadingRate) = Scalar(2) * zeta_ / omega_;
    // One jiffy's scatter lands in S and pushes the platform through k for that jiffy.
    scatter_ << Scalar(1), Scalar(0), impulse_jiffies_ * transition_(kReading, kStatic),
        impulse_jiffies_ * transition_(kReadingRate, kStatic);
  }

  // The stream has just reached the scale: `reading_g` is the newest sample, `static_guess_g` and
  // `rate_guess_g` (per jiffy) what is expected on it; both barely known yet. The platform is
  // where it reads.
  void start(Scalar reading_g, Scalar previous_reading_g, Scalar static_guess_g, Scalar rate_guess_g,
             Scalar weight_spread_g, Scalar rate_spread_g) {
    reference_g_ = reading_g;
    x_ << static_guess_g - reading_g, rate_guess_g, Scalar(0), reading_g - previous_reading_g;
    P_.setZero();
    P_(kStatic, kStatic) = weight_spread_g * weight_spread_g;
    P_(kRate, kRate) = rate_spread_g * rate_spread_g;
    P_(kReading, kReading) = tuning_.sample_noise_g * tuning_.sample_noise_g;
    P_(kReadingRate, kReadingRate) = weight_spread_g * weight_spread_g;
    outliers_in_a_row_ = 0;
    rejected_ = 0;
    started_ = true;
  }
  bool started() const { return started_; }
  // The flow is about to change by up to `spread_g` per jiffy (the valve moves): let the rate go.
  void expect_rate_change(Scalar spread_g) { P_(kRate, kRate) += spread_g * spread_g; }
  void stop() { started_ = false; }

  // One sample per jiffy; returns false when the sample was set aside as an outlier.
  bool observe(Scalar reading_g) {
    predict();
    const Scalar innovation = (reading_g - reference_g_) - reads_.dot(x_);
    const Scalar noise = tuning_.sample_noise_g * tuning_.sample_noise_g;
    const Vector p_reads = P_ * reads_;
    const Scalar innovation_variance = reads_.dot(p_reads) + noise;
    const Scalar limit = tuning_.outlier_sigmas * tuning_.outlier_sigmas * innovation_variance;
    if (innovation * innovation > limit && ++outliers_in_a_row_ <= tuning_.outliers_before_accepting) {
      ++rejected_;
      return false;
    }
    outliers_in_a_row_ = 0;
    const Vector gain = p_reads / innovation_variance;
    x_ += gain * innovation;
    // Joseph form: keeps P symmetric and positive in float.
    const Matrix i_kh = Matrix::Identity() - gain * reads_.transpose();
    P_ = i_kh * P_ * i_kh.transpose() + gain * noise * gain.transpose();
    return true;
  }

  Scalar static_g() const { return reference_g_ + x_(kStatic); }
  Scalar rate_g_per_jiffy() const { return x_(kRate); }
  // The force as grams without the ringing: what the reading would be on a rigid scale.
  Scalar equilibrium_g() const { return static_g() + impulse_jiffies_ * x_(kRate); }
  // What the reading holds beyond the force: the platform's ringing (as the load cell reads it).
  Scalar ringing_g() const { return reads_.dot(x_) - x_(kStatic) - impulse_jiffies_ * x_(kRate); }
  Scalar static_sd_g() const { return std::sqrt(std::fmax(P_(kStatic, kStatic), Scalar(0))); }
  Scalar rate_sd_g() const { return std::sqrt(std::fmax(P_(kRate, kRate), Scalar(0))); }
  unsigned rejected_samples() const { return rejected_; }

 private:
  void predict() {
    x_ = transition_ * x_;
    P_ = transition_ * P_ * transition_.transpose();
    // White noise on the mean rate's change, integrated over the jiffy into S (q/3, q/2, q).
    const Scalar q = tuning_.rate_walk_g * tuning_.rate_walk_g;
    P_(kStatic, kStatic) += q / Scalar(3);
    P_(kStatic, kRate) += q / Scalar(2);
    P_(kRate, kStatic) += q / Scalar(2);
    P_(kRate, kRate) += q;
    P_.noalias() += (tuning_.landing_scatter_g * tuning_.landing_scatter_g) * scatter_ * scatter_.transpose();
  }

  // exp(A) over one jiffy for x' = A x. A rigid scale (omega 0) reads the force itself.
  static Matrix discretize(Scalar omega, Scalar zeta, Scalar impulse_jiffies) {
    Matrix a = Matrix::Zero();
    a(kStatic, kRate) = Scalar(1);
    if (!(omega > Scalar(0))) {
      Matrix rigid = Matrix::Identity() + a;
      rigid.row(kReading) << Scalar(1), Scalar(1) + impulse_jiffies, Scalar(0), Scalar(0);
      rigid.row(kReadingRate).setZero();
      return rigid;
    }
    a(kReading, kReadingRate) = Scalar(1);
    a(kReadingRate, kStatic) = omega * omega;
    a(kReadingRate, kRate) = omega * omega * impulse_jiffies;
    a(kReadingRate, kReading) = -omega * omega;
    a(kReadingRate, kReadingRate) = Scalar(-2) * zeta * omega;
    // Taylor series on A / 2^s, squared s times. The rate column is large (k ~ 50 jiffies) but
    // enters linearly: the series converges as fast as the oscillator's block, whose norm is kept
    // below 1/4.
    int squarings = 1;
    Scalar block_norm = (omega * omega + Scalar(2) * zeta * omega + Scalar(1)) / Scalar(2);
    while (block_norm > Scalar(0.25) && squarings < 12) {
      block_norm /= Scalar(2);
      ++squarings;
    }
    const Matrix scaled = a / Scalar(1 << squarings);
    Matrix term = Matrix::Identity();
    Matrix sum = Matrix::Identity();
    for (int k = 1; k <= 10; ++k) {
      term = (term * scaled) / Scalar(k);
      sum += term;
    }
    for (int i = 0; i < squarings; ++i) sum = sum * sum;
    return sum;
  }

  Tuning tuning_{};
  Scalar omega_ = Scalar(-1);
  Scalar zeta_ = Scalar(0);
  Scalar impulse_jiffies_ = Scalar(0);
  Vector scatter_ = Vector::Zero();
  Vector reads_ = Vector::Unit(kReading);
  Matrix transition_ = Matrix::Identity();
  Vector x_ = Vector::Zero();
  Matrix P_ = Matrix::Zero();
  Scalar reference_g_ = Scalar(0);
  int outliers_in_a_row_ = 0;
  unsigned rejected_ = 0;
  bool started_ = false;
};

}  // namespace dynweigh::model
