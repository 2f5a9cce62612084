#include "fill_ceiling.hpp"

#include <algorithm>
#include <cmath>

#include "dynweigh/model/beverloo.hpp"
#include "dynweigh/model/bore_area.hpp"
#include "dynweigh/sim/plant.hpp"

namespace dynweigh::tools {
namespace {

// The pulses' hold times: every millisecond up to 60 ms at half open (where a pulse is a few grams and
// its scatter is the jitter's), then coarser up to 0.4 s, half and full open.
constexpr double kFinePulseS = 0.060;
constexpr double kLongestPulseS = 0.400;
constexpr int kBlindTimes = 80;             // the first opening's hold times, up to kBlindReach x the full-flow time
constexpr double kBlindReach = 1.5;
constexpr double kLongestBlindS = 3.0;      // a longer fill is closed on its measured stream, not blind
constexpr int kGridPerLimit = 20;           // the deficit's grid: a twentieth of the limit
constexpr double kLargestDeficitLimits = 40.0;
constexpr int kIdealAims = 200;
constexpr int kIdealQuantiles = 100;
constexpr int kDrawnFills = 4000;
constexpr int kDrawnSeries = 4000;
constexpr double kAimShares[] = {0.2, 0.3, 0.4, 0.55, 0.7, 1.0};

// The plant's released mass (g) for the valve held `command` for `hold_s` from rest, per seed.
std::vector<double> held_samples(const sim::Scene& scene, schema::ValveCommand command, double hold_s, int samples) {
  std::vector<double> grams;
  grams.reserve(std::size_t(samples));
  const double after_s = scene.valve.dead_time_s + 6.0 * scene.valve.dead_time_jitter_s + scene.valve.full_stroke_s + 0.05;
  for (int k = 0; k < samples; ++k) {
    sim::Plant plant(scene, 5000 + std::uint64_t(k));
    plant.advance(0.05);
    plant.command_valve(command);
    plant.advance(hold_s);
    plant.command_valve(schema::ValveCommand::closed);
    plant.advance(after_s);
    grams.push_back(plant.truth().released_kg * 1000.0);
  }
  return grams;
}

// The standard normal's quantile, by bisection of erfc (set-up only).
double normal_quantile(double p) {
  double low = -8.0, high = 8.0;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (low + high);
    (0.5 * std::erfc(-mid / std::sqrt(2.0)) < p ? low : high) = mid;
  }
  return 0.5 * (low + high);
}

// The chance of ending within the aimed band from each certified deficit on a grid, with 0..pulses
// pulses left, and the action that achieves it (-1: none now).
class DeficitPolicy {
 public:
  DeficitPolicy(const CeilingActions& actions, double limit_g, double aim_g, int pulses)
      : actions_(actions), step_g_(limit_g / kGridPerLimit), aim_g_(aim_g),
        lowest_(-int(std::ceil(aim_g / step_g_)) - 1),
        count_(int(kLargestDeficitLimits * limit_g / step_g_) - lowest_ + 1),
        chance_(std::size_t(pulses) + 1, std::vector<double>(std::size_t(count_))),
        action_(std::size_t(pulses) + 1, std::vector<int>(std::size_t(count_), -1)) {
    for (int i = 0; i < count_; ++i) chance_[0][std::size_t(i)] = std::abs(deficit_at(i)) <= aim_g_ + 1e-9 ? 1.0 : 0.0;
    for (int left = 1; left <= pulses; ++left) solve(left);
  }

  double chance(int left, double deficit_g) const {
    if (deficit_g < -aim_g_ - 1e-9) return 0.0;
    const double x = std::max(0.0, deficit_g / step_g_ - lowest_);
    if (x >= count_ - 1) return 0.0;
    const int i = int(x);
    const double share = x - i;
    const auto& c = chance_[std::size_t(left)];
    return c[std::size_t(i)] * (1.0 - share) + c[std::size_t(i) + 1] * share;
  }
  // The pulse to give with `left` pulses left, or -1.
  int action(int left, double deficit_g) const {
    const double x = deficit_g / step_g_ - lowest_;
    if (x < 0.0 || x >= count_ - 1) return -1;
    return action_[std::size_t(left)][std::size_t(std::lround(x))];
  }

 private:
  double deficit_at(int i) const { return (i + lowest_) * step_g_; }
  void solve(int left) {
    for (int i = 0; i < count_; ++i) {
      const double deficit = deficit_at(i);
      double best = chance_[std::size_t(left) - 1][std::size_t(i)];  // no pulse now, one later
      int best_action = -1;
      for (std::size_t a = 0; deficit > 0.0 && a < actions_.pulses.size(); ++a) {
        double sum = 0.0;
        for (double grams : actions_.pulses[a]) sum += chance(left - 1, deficit - grams);
        const double mean = sum / double(actions_.pulses[a].size());
        if (mean > best + 1e-12) {
          best = mean;
          best_action = int(a);
        }
      }
      chance_[std::size_t(left)][std::size_t(i)] = best;
      action_[std::size_t(left)][std::size_t(i)] = best_action;
    }
  }

  const CeilingActions& actions_;
  double step_g_, aim_g_;
  int lowest_, count_;
  std::vector<std::vector<double>> chance_;
  std::vector<std::vector<int>> action_;
};

// The first closes as samples of the deficit each leaves: blind holds, and ideal closes aimed short.
std::vector<std::vector<double>> first_closes(const CeilingActions& actions, double target_g, double largest_g) {
  std::vector<std::vector<double>> closes;
  for (const auto& held : actions.blind) {
    std::vector<double> deficits;
    for (double grams : held) deficits.push_back(target_g - grams);
    closes.push_back(deficits);
  }
  std::vector<double> z;
  for (int k = 0; k < kIdealQuantiles; ++k) z.push_back(normal_quantile((k + 0.5) / kIdealQuantiles));
  for (double sigma : {actions.ideal_full_sigma_g, actions.ideal_half_sigma_g}) {
    for (int j = 0; j <= kIdealAims; ++j) {
      std::vector<double> deficits;
      for (double q : z) deficits.push_back(largest_g * j / kIdealAims + sigma * q);
      closes.push_back(deficits);
    }
  }
  return closes;
}

struct XorShift {
  std::uint64_t state = 88172645463325252ULL;
  std::uint64_t next() {
    state ^= state << 13;
    state ^= state >> 7;
    state ^= state << 17;
    return state;
  }
  template <typename T>
  const T& pick(const std::vector<T>& v) { return v[next() % v.size()]; }
};

// One policy (aiming within `aim_g`), its fills drawn again: the chance within the limit and the
// chance a series of `steady_fills` meets the steady class.
FillCeiling policy_ceiling(const CeilingActions& actions, double target_g, const CeilingLimits& limits, double aim_g,
                           int pulses, std::uint32_t steady_fills) {
  const DeficitPolicy policy(actions, limits.limit_g, aim_g, pulses);
  const auto closes = first_closes(actions, target_g, kLargestDeficitLimits * limits.limit_g);
  std::size_t best = 0;
  double best_chance = -1.0;
  for (std::size_t c = 0; c < closes.size(); ++c) {
    double sum = 0.0;
    for (double deficit : closes[c]) sum += policy.chance(pulses, deficit);
    if (sum > best_chance) {
      best_chance = sum;
      best = c;
    }
  }
  XorShift random;
  std::vector<double> errors(kDrawnFills);
  int within = 0;
  for (double& error : errors) {
    double deficit = random.pick(closes[best]);
    for (int left = pulses; left >= 1; --left) {
      const int a = policy.action(left, deficit);
      if (a >= 0) deficit -= random.pick(actions.pulses[std::size_t(a)]);
    }
    error = -deficit;
    within += std::abs(error) <= limits.limit_g;
  }
  int steady = 0;
  std::vector<double> series(steady_fills);
  for (int s = 0; s < kDrawnSeries; ++s) {
    double mean = 0.0;
    for (double& e : series) mean += (e = random.pick(errors)) / double(steady_fills);
    double deviation = 0.0;
    for (double e : series) deviation = std::max(deviation, std::abs(e - mean));
    steady += deviation <= limits.limit_g && std::abs(mean) <= limits.bias_limit_g;
  }
  return {double(within) / kDrawnFills, double(steady) / kDrawnSeries};
}

}  // namespace

CeilingActions sample_ceiling_actions(const sim::Scene& scene, double target_g, int samples) {
  CeilingActions a;
  for (double hold = 0.001; hold <= kFinePulseS + 1e-9; hold += 0.001) {
    a.pulses.push_back(held_samples(scene, schema::ValveCommand::half, hold, samples));
  }
  for (double hold = kFinePulseS + 0.005; hold <= kLongestPulseS + 1e-9; hold += 0.005) {
    a.pulses.push_back(held_samples(scene, schema::ValveCommand::half, hold, samples));
  }
  for (double hold = 0.010; hold <= kLongestPulseS + 1e-9; hold += 0.005) {
    a.pulses.push_back(held_samples(scene, schema::ValveCommand::open, hold, samples));
  }
  const model::BeverlooMaterial<double> material{scene.silo.beverloo_C, scene.silo.beverloo_k, scene.silo.grain_d_m,
                                                 scene.silo.bulk_density};
  const double full_kg_s = model::beverloo_discharge_kg_s(material, scene.g, scene.silo.bore_m);
  const double half_kg_s = model::discharge_at_stroke_kg_s(material, scene.g, scene.silo.bore_m, 0.5);
  const double full_flow_s = full_kg_s > 0.0 ? target_g / 1000.0 / full_kg_s : 0.0;
  if (full_flow_s > 0.0 && full_flow_s <= kLongestBlindS) {
    const double longest = kBlindReach * full_flow_s + scene.valve.dead_time_s + scene.valve.full_stroke_s;
    for (int j = 1; j <= kBlindTimes; ++j) {
      a.blind.push_back(held_samples(scene, schema::ValveCommand::open, longest * j / kBlindTimes, samples));
    }
  }
  a.ideal_full_sigma_g = 1000.0 * full_kg_s * scene.valve.dead_time_jitter_s;
  a.ideal_half_sigma_g = 1000.0 * half_kg_s * scene.valve.dead_time_jitter_s;
  return a;
}

FillCeiling fill_ceiling(const CeilingActions& actions, double target_g, const CeilingLimits& limits, int pulses,
                         std::uint32_t steady_fills) {
  FillCeiling best;
  for (double share : kAimShares) {
    const FillCeiling c = policy_ceiling(actions, target_g, limits, share * limits.limit_g, pulses, steady_fills);
    if (share == 1.0) best.first = c.first;
    best.steady = std::max(best.steady, c.steady);
  }
  return best;
}

}  // namespace dynweigh::tools
