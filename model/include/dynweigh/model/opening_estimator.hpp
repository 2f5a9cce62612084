#pragma once
// The instant the first grains hit the scale after the open command, and from it the valve's
// dead time (thesis: the first impulse and the flow rate reveal the material and the valve).
//
// Why not the jiffy the reading first rises, nor a threshold crossing interpolated within it: the
// platform is a lightly damped low-pass, so after the onset t0 the reading grows like (t - t0)^2
// for a step of the equilibrium and like (t - t0)^3 for a ramp. A crossing misses the onset by
// several milliseconds (up to 7 ms late for the default 80 ms stroke, 10 ms for a slow one, a few
// early for a steep onset), by an amount that depends on where in the jiffy the onset fell and on
// how fast the flow ramps. So once two rising samples confirm the impact, the onset is fitted:
// the equilibrium is a step plus a ramp from t0 (the stream's momentum arrives at once, its rate
// grows while the gate strokes), seen through the platform's step and ramp responses, over the
// last quiet samples and the first risen ones.
//
// What it cannot see: a rate that rises and levels off within about three jiffies looks like a
// step at the middle of its rise, so the onset is placed up to half that rise late.
#include <algorithm>
#include <cmath>
#include <cstddef>

namespace dynweigh::model {

// The platform as the onset sees it: with the empty container, since the load is grams yet.
template <typename Scalar>
struct PlatformResponse {
  Scalar natural_hz = 0;     // 0: a rigid scale, the reading is the equilibrium itself
  Scalar damping_ratio = 0;  // below 1: the platform rings
  // Whether the cell carries the damper's force as well as the spring's (the plant's platform
  // does): the reading then leads the deflection by 2 zeta / omega, 1.3 ms at 12 Hz.
  bool reads_damper_force = false;
};

// Unit step and unit ramp responses of the platform, tau seconds after the input began.
template <typename Scalar>
struct PlatformOnsetShapes {
  Scalar step = 0;
  Scalar ramp_s = 0;  // response to an input growing by 1 per second
};

template <typename Scalar>
PlatformOnsetShapes<Scalar> platform_onset_shapes(const PlatformResponse<Scalar>& platform, Scalar tau_s) {
  if (!(tau_s > Scalar(0))) return {};
  if (!(platform.natural_hz > Scalar(0))) return {Scalar(1), tau_s};
  const Scalar omega = Scalar(2) * Scalar(M_PI) * platform.natural_hz;
  const Scalar zeta = std::clamp(platform.damping_ratio, Scalar(0), Scalar(0.99));
  const Scalar sigma = zeta * omega;
  const Scalar omega_d = omega * std::sqrt(Scalar(1) - zeta * zeta);
  const Scalar decay = std::exp(-sigma * tau_s);
  const Scalar c = std::cos(omega_d * tau_s), s = std::sin(omega_d * tau_s);
  // Each response is its steady part plus the free ringing that starts it at rest (deflection
  // and rate zero at tau = 0). The ramp's steady part lags the input by 2 zeta / omega.
  const Scalar lag_s = Scalar(2) * zeta / omega;
  PlatformOnsetShapes<Scalar> shapes;
  shapes.step = Scalar(1) - decay * (c + sigma / omega_d * s);
  shapes.ramp_s = tau_s - lag_s + decay * (lag_s * c + (sigma * lag_s - Scalar(1)) / omega_d * s);
  if (platform.reads_damper_force) {
    // Spring plus damper: the deflection plus 2 zeta / omega times its rate.
    shapes.ramp_s += lag_s * shapes.step;
    shapes.step += lag_s * omega * omega / omega_d * decay * s;
  }
  return shapes;
}

template <typename Scalar>
class OpeningEstimator {
 public:
  // Risen samples the fit waits for: enough to tell a step from a ramp, few enough that the
  // stroke of a fast valve has not ended and the static mass is still small beside the impulse.
  static constexpr std::size_t kRisenSamples = 4;
  // Quiet samples before the rise: they hold the fit at zero before the onset.
  static constexpr std::size_t kQuietSamples = 2;

  explicit OpeningEstimator(const PlatformResponse<Scalar>& platform) : platform_(platform) {}

  // At the jiffy the valve is commanded open; that jiffy's reading is sample 0.
  void start(Scalar baseline_g, Scalar jiffy_s, Scalar noise_g) {
    baseline_g_ = baseline_g;
    jiffy_s_ = jiffy_s;
    // Far above the noise and the 1 g division: a quiet scale never crosses it twice running.
    threshold_g_ = std::max(Scalar(5), Scalar(8) * noise_g);
    search_ = Search{};
    count_ = 0;
    first_risen_ = 0;
    rising_ = false;
    found_ = false;
    onset_ = {};
  }

  // One reading per jiffy, from the open command on. Does nothing before start() or once found.
  // Once the rise is confirmed the readings are no longer needed: the fit runs over the next
  // jiffies, kFitsPerJiffy trial onsets at a time, so no jiffy of a control loop pays for all.
  void observe(Scalar reading_g) {
    if (found_ || !(jiffy_s_ > Scalar(0))) return;
    if (search_.phase != Search::Phase::idle) return continue_search();
    const std::size_t k = count_++;
    history_[k % kHistory] = reading_g - baseline_g_;
    // Two running samples above the threshold, the second not lower: a lone spike falls back
    // below it, and the platform's first half period only rises.
    if (!rising_ && k >= 1 && above(k - 1) && above(k) && at(k) >= at(k - 1)) {
      rising_ = true;
      first_risen_ = k - 1;
    }
    if (rising_ && k + 1 >= first_risen_ + kRisenSamples) begin_search();
  }

  bool impact_found() const { return found_; }
  // Seconds from the open command to the first impact; 0 until found.
  Scalar first_impact_s() const { return found_ ? onset_.time_s : Scalar(0); }
  // The equilibrium's step (g) and ramp (g/s) at the onset: the stream's first momentum and its
  // growth while the gate strokes.
  Scalar onset_step_g() const { return onset_.step_g; }
  Scalar onset_ramp_g_s() const { return onset_.ramp_g_s; }
  // The first impact less the fall from rest over `fall_height_m`, since the first grains leave
  // the orifice at almost no speed. An effective dead time, as the scale sees the valve: the
  // command-to-motion delay, plus the part of the stroke before enough grains pass to weigh, less
  // what the faster grains that follow gain on the first ones, as the step-and-ramp fit places
  // the onset. 0 until found.
  Scalar dead_time_s(Scalar fall_height_m, Scalar g) const {
    if (!found_) return Scalar(0);
    return onset_.time_s - std::sqrt(Scalar(2) * fall_height_m / g);
  }
  Scalar threshold_g() const { return threshold_g_; }
  std::size_t samples() const { return count_; }

 private:
  static constexpr std::size_t kFitSamples = kQuietSamples + kRisenSamples;
  static constexpr std::size_t kHistory = 8;
  static_assert(kHistory >= kFitSamples, "the fit reads its samples from the history");
  // The fit runs once per dose: a 0.5 ms scan over two jiffies, then a golden section refines
  // the best cell to well below a microsecond; about 70 fits of six samples in all.
  static constexpr int kGridPoints = 41;
  static constexpr int kRefineIterations = 24;
  // Trial onsets per jiffy: ~1,600 instructions each on a Cortex-M4F, so the search costs a
  // control jiffy about 10,000 and ends ~12 jiffies after the rise is confirmed.
  static constexpr int kFitsPerJiffy = 6;
  static constexpr Scalar kGolden = Scalar(0.6180339887498949);

  struct Onset {
    Scalar time_s = 0;
    Scalar step_g = 0;
    Scalar ramp_g_s = 0;
    Scalar residual = 0;
  };

  Scalar at(std::size_t k) const { return history_[k % kHistory]; }
  bool above(std::size_t k) const { return at(k) > threshold_g_; }
  Scalar time_of(std::size_t k) const { return Scalar(k) * jiffy_s_; }
  std::size_t first_quiet() const { return first_risen_ >= kQuietSamples ? first_risen_ - kQuietSamples : 0; }

  // Least squares of step and ramp for an onset at t0, neither negative (material does not leave
  // the scale at the opening). The ramp is counted per jiffy so the normal equations stay
  // balanced in float; the residual is summed from the residuals, not expanded from the sums,
  // which would cancel to nothing in float.
  Onset fit_at(Scalar t0) const {
    Scalar step_shape[kFitSamples] = {}, ramp_shape[kFitSamples] = {}, y[kFitSamples] = {};
    std::size_t n = 0;
    for (std::size_t k = first_quiet(); k < first_risen_ + kRisenSamples; ++k) {
      if (k < first_risen_ && std::fabs(at(k)) > threshold_g_) continue;  // a spike is not quiet
      const PlatformOnsetShapes<Scalar> shape = platform_onset_shapes(platform_, time_of(k) - t0);
      step_shape[n] = shape.step;
      ramp_shape[n] = shape.ramp_s / jiffy_s_;
      y[n] = at(k);
      ++n;
    }
    Scalar ss = 0, sr = 0, rr = 0, ys = 0, yr = 0;
    for (std::size_t i = 0; i < n; ++i) {
      ss += step_shape[i] * step_shape[i];
      sr += step_shape[i] * ramp_shape[i];
      rr += ramp_shape[i] * ramp_shape[i];
      ys += y[i] * step_shape[i];
      yr += y[i] * ramp_shape[i];
    }
    Scalar step = -1, slope = -1;
    const Scalar det = ss * rr - sr * sr;
    if (det > Scalar(1e-6) * ss * rr) {
      step = (ys * rr - yr * sr) / det;
      slope = (yr * ss - ys * sr) / det;
    }
    if (!(step >= Scalar(0) && slope >= Scalar(0))) {
      // On the boundary: the one of the two alone that explains more.
      const Scalar step_only = ss > Scalar(0) ? std::max(Scalar(0), ys / ss) : Scalar(0);
      const Scalar slope_only = rr > Scalar(0) ? std::max(Scalar(0), yr / rr) : Scalar(0);
      const bool use_step = step_only * ys >= slope_only * yr;
      step = use_step ? step_only : Scalar(0);
      slope = use_step ? Scalar(0) : slope_only;
    }
    Scalar residual = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const Scalar r = y[i] - step * step_shape[i] - slope * ramp_shape[i];
      residual += r * r;
    }
    return {t0, step, slope / jiffy_s_, residual};
  }

  // A grid of trial onsets over the two jiffies before the first risen sample (the quiet ones
  // would have risen by then), then a golden section on the best cell.
  struct Search {
    enum class Phase { idle, grid, golden } phase = Phase::idle;
    Scalar earliest = 0, spacing = 0;
    int next = 0;  // grid point, or golden iteration
    int best_index = 0;
    Onset best{};
    Scalar low = 0, high = 0, a = 0, b = 0;
    Onset fa{}, fb{};
  };

  void begin_search() {
    const Scalar latest = time_of(first_risen_);
    search_ = Search{};
    search_.phase = Search::Phase::grid;
    search_.earliest = std::max(Scalar(0), latest - Scalar(2) * jiffy_s_);
    search_.spacing = (latest - search_.earliest) / Scalar(kGridPoints - 1);
    search_.best = fit_at(search_.earliest);
    search_.next = 1;
  }

  void continue_search() {
    for (int fits = 0; fits < kFitsPerJiffy && !found_; ++fits) {
      if (search_.phase == Search::Phase::grid) {
        grid_step();
      } else {
        golden_step();
      }
    }
  }

  void grid_step() {
    Search& s = search_;
    const Onset candidate = fit_at(s.earliest + s.spacing * Scalar(s.next));
    if (candidate.residual < s.best.residual) {
      s.best = candidate;
      s.best_index = s.next;
    }
    if (++s.next < kGridPoints) return;
    s.low = s.earliest + s.spacing * Scalar(std::max(s.best_index - 1, 0));
    s.high = s.earliest + s.spacing * Scalar(std::min(s.best_index + 1, kGridPoints - 1));
    s.a = s.high - kGolden * (s.high - s.low);
    s.b = s.low + kGolden * (s.high - s.low);
    s.fa = fit_at(s.a);
    s.fb = fit_at(s.b);
    s.phase = Search::Phase::golden;
    s.next = 0;
  }

  void golden_step() {
    Search& s = search_;
    if (s.fa.residual <= s.fb.residual) {
      s.high = s.b, s.b = s.a, s.fb = s.fa;
      s.a = s.high - kGolden * (s.high - s.low);
      s.fa = fit_at(s.a);
    } else {
      s.low = s.a, s.a = s.b, s.fa = s.fb;
      s.b = s.low + kGolden * (s.high - s.low);
      s.fb = fit_at(s.b);
    }
    if (++s.next < kRefineIterations) return;
    const Onset& refined = s.fa.residual <= s.fb.residual ? s.fa : s.fb;
    onset_ = refined.residual <= s.best.residual ? refined : s.best;
    found_ = true;
  }

  PlatformResponse<Scalar> platform_;
  Scalar baseline_g_ = 0;
  Scalar jiffy_s_ = 0;
  Scalar threshold_g_ = 0;
  Scalar history_[kHistory] = {};
  std::size_t count_ = 0;
  std::size_t first_risen_ = 0;
  bool rising_ = false;
  bool found_ = false;
  Onset onset_{};
  Search search_{};
};

}  // namespace dynweigh::model
