#pragma once
// Dynamic weighing: the final static weight from the platform's free, damped ringing, long before
// the ringing has died away. After the last grain has landed the reading is W plus a damped
// sinusoid, which obeys y[n] - W = c1 (y[n-1] - W) + c2 (y[n-2] - W) exactly (Prony). So
// y[n] = c1 y[n-1] + c2 y[n-2] + d is linear in (c1, c2, d), solved by least squares over a
// window, and W = d / (1 - c1 - c2). The fit's covariance gives W's standard error: the result is
// certified when that error is small, not when a filter has settled.
// That fit's regressors are readings too, and carry their noise: on a slow platform (5 Hz, twenty
// samples a period) 1 - c1 - c2 is small, W's error many times the noise, and the decay it finds
// biased fast. So the damped sinusoid y[n] = W + r^n (A cos(n theta) + B sin(n theta)) is fitted
// again directly to the readings, where the noise is in the readings only: started from the Prony
// fit's decay and frequency, all five parameters by Gauss-Newton steps, W's standard error
// from the five's covariance (taken kDirectErrorFactor times). The estimate with the smaller error
// counts (docs/strategies.md, Dynamic weighing).
#include <Eigen/Dense>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace dynweigh::model {

template <typename Scalar, std::size_t Capacity>
class DampedSettlingFit {
 public:
  static_assert(Capacity >= 8, "a damped sinusoid needs a few periods of samples");
  static constexpr std::size_t kMinimumSamples = 12;
  // A fit from scratch takes up to kColdSteps Gauss-Newton steps, as many as fit in
  // kColdStepSamples samples' worth of work (one step on a full window): the jiffy's budget.
  static constexpr int kColdSteps = 3;
  static constexpr std::size_t kColdStepSamples = 96;
  // W's standard error from the direct fit holds for a single ringing in white noise. A real
  // reading's noise is not white (the converter filters it) and the last grains still nudge it, so
  // its error is taken this many times: on the plant family the results certified so are as close
  // to the truth as those of the Prony fit alone, whose error was pessimistic (docs/strategies.md).
  static constexpr Scalar kDirectErrorFactor = Scalar(3);
  static constexpr Scalar kShortestStepShare = Scalar(0.01);
  // A ringing that loses more than half its amplitude from one sample to the next is gone within a
  // few: nothing for the direct fit to follow.
  static constexpr Scalar kSlowestDecayPerSample = Scalar(0.5);

  void reset() {
    count_ = 0;
    head_ = 0;
    pushed_ = 0;
    warm_.valid = false;
  }
  void push(Scalar value) {
    samples_[head_] = value;
    head_ = (head_ + 1) % Capacity;
    if (count_ < Capacity) ++count_;
    ++pushed_;
  }
  std::size_t count() const { return count_; }
  // Forgets the `samples` oldest kept (all of them if fewer are kept): the next fit starts later.
  void drop_oldest(std::size_t samples) { count_ -= samples < count_ ? samples : count_; }

  struct Estimate {
    bool valid = false;
    Scalar final_value = 0;     // W
    Scalar standard_error = 0;  // of W, from the residuals
    Scalar residual_rms = 0;
  };

  // Not const: the direct fit starts from where the last one ended (see fit_directly()).
  Estimate fit() {
    Estimate e;
    if (count_ < kMinimumSamples) return e;
    // Relative to the newest sample: W is near it, so float keeps its resolution at full scale.
    const Scalar reference = at(count_ - 1);
    const PronySums sums = prony_sums(reference);
    Eigen::Matrix<Scalar, 3, 3> normal;
    normal << sums.xx11, sums.xx12, sums.x1, sums.xx12, sums.xx22, sums.x2, sums.x1, sums.x2, Scalar(count_ - 2);
    const Eigen::Matrix<Scalar, 3, 1> rhs(sums.xy1, sums.xy2, sums.y);
    const Eigen::LDLT<Eigen::Matrix<Scalar, 3, 3>> solver(normal);
    if (solver.info() != Eigen::Success) return e;
    const Eigen::Matrix<Scalar, 3, 1> c = solver.solve(rhs);
    const Scalar loop_gain = Scalar(1) - c(0) - c(1);
    if (!(std::fabs(loop_gain) > Scalar(1e-4))) return e;  // no decay: W is not identifiable yet
    const Scalar residual_sum = prony_residual_sum(reference, c(0), c(1), c(2));
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
    if (!e.valid) return e;
    const Estimate direct = fit_directly(c(0), c(1), reference);
    return direct.valid && direct.standard_error < e.standard_error ? direct : e;
  }

 private:
  // The Prony fit's normal equations: sums over n >= 2 of x1 = y[n-1], x2 = y[n-2] and y = y[n],
  // each less the reference. Written out, not as Eigen's rank updates: this runs every jiffy of a
  // settling over the whole window, and the Cortex-M's budget is per jiffy.
  struct PronySums {
    Scalar xx11 = 0, xx12 = 0, xx22 = 0, x1 = 0, x2 = 0, xy1 = 0, xy2 = 0, y = 0;
  };
  PronySums prony_sums(Scalar reference) const {
    PronySums s;
    Scalar older = 0, old = 0;
    std::size_t n = 0;
    for (const Run& run : runs()) {
      for (std::size_t i = 0; i < run.size; ++i, ++n) {
        const Scalar y = run.begin[i] - reference;
        if (n >= 2) {
          s.xx11 += old * old;
          s.xx12 += old * older;
          s.xx22 += older * older;
          s.x1 += old;
          s.x2 += older;
          s.xy1 += old * y;
          s.xy2 += older * y;
          s.y += y;
        }
        older = old;
        old = y;
      }
    }
    return s;
  }
  Scalar prony_residual_sum(Scalar reference, Scalar c1, Scalar c2, Scalar d) const {
    Scalar sum = 0, older = 0, old = 0;
    std::size_t n = 0;
    for (const Run& run : runs()) {
      for (std::size_t i = 0; i < run.size; ++i, ++n) {
        const Scalar y = run.begin[i] - reference;
        if (n >= 2) {
          const Scalar r = y - c1 * old - c2 * older - d;
          sum += r * r;
        }
        older = old;
        old = y;
      }
    }
    return sum;
  }

  // The kept samples, oldest first, as the ring's two runs: each pass loops over them with its body
  // written once, so that the compiler keeps the sums in registers (no index worked out per sample).
  struct Run {
    const Scalar* begin;
    std::size_t size;
  };
  std::array<Run, 2> runs() const {
    const std::size_t start = (head_ + Capacity - count_) % Capacity;
    const std::size_t first = start + count_ <= Capacity ? count_ : Capacity - start;
    return {Run{samples_ + start, first}, Run{samples_, count_ - first}};
  }

  // The model's parameters (W, A, B, r, theta): W less the fit's reference, the phases' amplitudes
  // at the oldest sample.
  using Parameters = Eigen::Matrix<Scalar, 5, 1>;

  // The last direct fit, for the next one to start from: W absolute, the phases at the sample
  // pushed `origin`-th.
  struct WarmStart {
    bool valid = false;
    Parameters p = Parameters::Zero();
    std::uint32_t origin = 0;
  };

  // y[n] = W + r^n (A cos(n theta) + B sin(n theta)), n from the oldest sample, by Gauss-Newton.
  // From scratch: (W, A, B) by linear least squares at the Prony fit's r and theta (the roots of
  // z^2 = c1 z + c2), then a few steps. Each later fit sees one sample more than the last and
  // starts from its result: one step each keeps up, and keeps the jiffy's work within the
  // Cortex-M's budget. Not without a ringing (real roots) or with one already gone. W's error from
  // the last step's system, its residuals less what the step took out.
  Estimate fit_directly(Scalar c1, Scalar c2, Scalar reference) {
    Estimate e;
    Parameters p;
    int steps = 1;
    if (!warm_start(reference, p)) {
      const std::size_t affordable = kColdStepSamples / count_;
      steps = affordable < 1 ? 1 : (affordable > std::size_t(kColdSteps) ? kColdSteps : int(affordable));
      if (!cold_start(c1, c2, reference, p)) return e;
    }
    warm_.valid = false;
    Eigen::Matrix<Scalar, 5, 5> normal;
    Eigen::Matrix<Scalar, 5, 1> rhs;
    Scalar residual_sum = 0, explained = 0;
    for (int step = 0; step < steps; ++step) {
      residual_sum = gauss_newton_system(reference, p, normal, rhs);
      const Eigen::LDLT<Eigen::Matrix<Scalar, 5, 5>> solver(normal);
      if (solver.info() != Eigen::Success) return e;
      const Parameters full_step = solver.solve(rhs);
      const Scalar share = share_within_bounds(p, full_step);
      if (!(share > Scalar(0))) return e;
      p += share * full_step;
      explained = share * rhs.dot(full_step);
    }
    const Eigen::LDLT<Eigen::Matrix<Scalar, 5, 5>> solver(normal);
    const Scalar variance = std::fmax(residual_sum - explained, Scalar(0)) / (Scalar(count_) - Scalar(5));
    Parameters w_only = Parameters::Zero();
    w_only(0) = Scalar(1);
    const Scalar w_variance = variance * w_only.dot(solver.solve(w_only));
    if (!std::isfinite(p(0)) || !(w_variance >= Scalar(0))) return e;
    warm_ = WarmStart{true, p, oldest()};
    warm_.p(0) += reference;
    e.valid = true;
    e.final_value = reference + p(0);
    e.standard_error = kDirectErrorFactor * std::sqrt(w_variance);
    e.residual_rms = std::sqrt(variance);
    return e;
  }

  bool cold_start(Scalar c1, Scalar c2, Scalar reference, Parameters& p) const {
    if (!(c1 * c1 + Scalar(4) * c2 < Scalar(0))) return false;
    const Scalar r = std::sqrt(-c2);
    if (!(r < Scalar(1)) || !(r > kSlowestDecayPerSample)) return false;
    const Scalar theta = std::acos(std::fmax(Scalar(-1), std::fmin(Scalar(1), c1 / (Scalar(2) * r))));
    Scalar cc = 0, cs = 0, ss = 0, sum_c = 0, sum_s = 0, cy = 0, sy = 0, sum_y = 0;
    Oscillation wave{r, std::cos(theta), std::sin(theta)};
    for (const Run& run : runs()) {
      for (std::size_t i = 0; i < run.size; ++i) {
        const Scalar y = run.begin[i] - reference;
        cc += wave.cosine * wave.cosine;
        cs += wave.cosine * wave.sine;
        ss += wave.sine * wave.sine;
        sum_c += wave.cosine;
        sum_s += wave.sine;
        cy += wave.cosine * y;
        sy += wave.sine * y;
        sum_y += y;
        wave.advance();
      }
    }
    Eigen::Matrix<Scalar, 3, 3> normal;
    normal << Scalar(count_), sum_c, sum_s, sum_c, cc, cs, sum_s, cs, ss;
    const Eigen::Matrix<Scalar, 3, 1> rhs(sum_y, cy, sy);
    const Eigen::LDLT<Eigen::Matrix<Scalar, 3, 3>> solver(normal);
    if (solver.info() != Eigen::Success) return false;
    const Eigen::Matrix<Scalar, 3, 1> phases = solver.solve(rhs);
    p << phases(0), phases(1), phases(2), r, theta;
    return std::isfinite(phases(0));
  }

  // The last fit's parameters, its phases carried to the present oldest sample:
  // r^(n+k) (A cos((n+k) t) + B sin((n+k) t)) = r^n (A' cos(n t) + B' sin(n t)).
  bool warm_start(Scalar reference, Parameters& p) const {
    if (!warm_.valid) return false;
    const std::uint32_t shift = oldest() - warm_.origin;
    if (shift > Capacity) return false;
    p = warm_.p;
    p(0) -= reference;
    const Scalar cos_t = std::cos(p(4)), sin_t = std::sin(p(4));
    for (std::uint32_t k = 0; k < shift; ++k) {
      const Scalar a = p(3) * (p(1) * cos_t + p(2) * sin_t);
      p(2) = p(3) * (p(2) * cos_t - p(1) * sin_t);
      p(1) = a;
    }
    return true;
  }

  // A Gauss-Newton step, shortened (halved) until the decay stays a decay: the share of it taken,
  // 0 if none would do.
  static Scalar share_within_bounds(const Parameters& p, const Parameters& step) {
    for (Scalar share = Scalar(1); share > kShortestStepShare; share *= Scalar(0.5)) {
      const Scalar r = p(3) + share * step(3);
      if (r < Scalar(1) && r > kSlowestDecayPerSample) return share;
    }
    return Scalar(0);
  }

  // J^T J and J^T e of the model at `p`, and the sum of squared residuals. J's rows are
  // (1, c, s, d, q): c and s the decaying cosine and sine, d = n (A c + B s) / r and
  // q = n (B c - A s) the derivatives in r and theta. Each entry of J^T J's upper triangle is a sum
  // of its own, written out: this runs every jiffy of a settling over the whole window, and the
  // Cortex-M's budget is per jiffy (a loop over the entries would keep them in memory).
  Scalar gauss_newton_system(Scalar reference, const Parameters& p, Eigen::Matrix<Scalar, 5, 5>& normal,
                             Eigen::Matrix<Scalar, 5, 1>& rhs) const {
    Scalar sc = 0, ss_ = 0, sd = 0, sq = 0;                  // row 0: the sums of c, s, d, q
    Scalar cc = 0, cs = 0, cd = 0, cq = 0, s2 = 0, sdd = 0, sqq = 0, dd = 0, dq = 0, qq = 0;
    Scalar e0 = 0, e1 = 0, e2 = 0, e3 = 0, e4 = 0, residual_sum = 0, n = 0;
    const Scalar per_decay = Scalar(1) / p(3);
    const Scalar w = p(0), a = p(1), b = p(2);
    Oscillation wave{p(3), std::cos(p(4)), std::sin(p(4))};
    for (const Run& run : runs()) {
      for (std::size_t i = 0; i < run.size; ++i) {
        const Scalar c = wave.cosine, s = wave.sine;
        const Scalar in_phase = a * c + b * s;
        const Scalar d = n * in_phase * per_decay, q = n * (b * c - a * s);
        const Scalar e = run.begin[i] - reference - w - in_phase;
        sc += c;
        ss_ += s;
        sd += d;
        sq += q;
        cc += c * c;
        cs += c * s;
        cd += c * d;
        cq += c * q;
        s2 += s * s;
        sdd += s * d;
        sqq += s * q;
        dd += d * d;
        dq += d * q;
        qq += q * q;
        e0 += e;
        e1 += c * e;
        e2 += s * e;
        e3 += d * e;
        e4 += q * e;
        residual_sum += e * e;
        n += Scalar(1);
        wave.advance();
      }
    }
    normal << Scalar(count_), sc, ss_, sd, sq,  //
        sc, cc, cs, cd, cq,                     //
        ss_, cs, s2, sdd, sqq,                  //
        sd, cd, sdd, dd, dq,                    //
        sq, cq, sqq, dq, qq;
    rhs << e0, e1, e2, e3, e4;
    return residual_sum;
  }

  // r^n cos(n theta) and r^n sin(n theta), one sample further each step (a rotation and a decay).
  struct Oscillation {
    Scalar decay, cos_step, sin_step;
    Scalar cosine = Scalar(1), sine = Scalar(0);
    void advance() {
      const Scalar c = decay * (cosine * cos_step - sine * sin_step);
      sine = decay * (cosine * sin_step + sine * cos_step);
      cosine = c;
    }
  };

  std::uint32_t oldest() const { return pushed_ - std::uint32_t(count_); }  // the pushes before it

  Scalar at(std::size_t i) const {  // i = 0 is the oldest kept
    return samples_[(head_ + Capacity - count_ + i) % Capacity];
  }
  Scalar samples_[Capacity] = {};
  std::size_t count_ = 0;
  std::size_t head_ = 0;
  std::uint32_t pushed_ = 0;
  WarmStart warm_{};
};

}  // namespace dynweigh::model
