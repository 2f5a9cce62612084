#include "dynweigh/firmware/dose_history.hpp"

#include <cmath>

namespace dynweigh::firmware {
namespace {
constexpr float kSecondsPerUnit = 1e-4f;
constexpr float kLargestUnits = 65535.0f;
constexpr float kLeastK = 1.0f;
constexpr float kMostK = 4.0f;
constexpr float kPriorK = 2.0f;  // doses all at one open time tell no slope: a gate opening halfway
// One dose tells no slope either, and beyond it the line through it is what overdoses: the curve
// through it grows as a gate still opening lets the fill grow (docs/plant-family.md, The second
// and third blind closes). Two doses tell it badly: each fill scatters by the valve's jitter and
// the flow's start-up, and two a fifth apart in open time showed no growth at all on valves whose
// fill then grew fourfold. Beyond the longer of two, the curve grows at least as through one.
constexpr float kOneDoseK = 3.0f;
constexpr std::uint8_t kDosesThatTellASlopeBeyond = 3;
constexpr float kLeastWeight = 1e-3f;
}  // namespace

float DoseHistory::PowerLaw::fill_g(float open_s) const {
  return valid && open_s > 0.0f ? std::exp(log_a + k * std::log(open_s)) : 0.0f;
}

float DoseHistory::PowerLaw::growth_g_per_s(float open_s, float fill_there_g) const {
  return valid && open_s > 0.0f ? k * fill_there_g / open_s : 0.0f;
}

void DoseHistory::add(float open_s, float final_g) {
  const float units = std::round(open_s / kSecondsPerUnit), grams = std::round(final_g);
  if (!(units >= 1.0f && units <= kLargestUnits && grams >= kLightestG && grams <= kLargestUnits)) return;
  entries_[next_] = Entry{std::uint16_t(units), std::uint16_t(grams)};
  next_ = std::uint8_t((next_ + 1) % kDoses);
  if (count_ < kDoses) ++count_;
}

bool DoseHistory::restore(const Entry (&entries)[kDoses], std::uint8_t count, std::uint8_t next) {
  if (count > kDoses || next >= kDoses || (count < kDoses && next != count)) return false;
  for (std::size_t i = 0; i < count; ++i) {
    if (entries[i].open_100us == 0 || float(entries[i].final_g) < kLightestG) return false;
  }
  for (std::size_t i = 0; i < kDoses; ++i) entries_[i] = i < count ? entries[i] : Entry{};
  count_ = count;
  next_ = next;
  return true;
}

DoseHistory::PowerLaw DoseHistory::cube_through(const Entry& dose) {
  PowerLaw law;
  law.k = kOneDoseK;
  law.log_a = std::log(float(dose.final_g)) - kOneDoseK * std::log(float(dose.open_100us) * kSecondsPerUnit);
  law.valid = std::isfinite(law.log_a);
  return law;
}

// Weighted least squares of ln(fill) on ln(t), the weights a Gaussian in ln(t) about `open_s`.
DoseHistory::PowerLaw DoseHistory::near(float open_s) const {
  PowerLaw law;
  if (count_ == 0 || !(open_s > 0.0f)) return law;
  if (count_ == 1) return cube_through(entries_[0]);
  const float x0 = std::log(open_s);
  float x[kDoses], y[kDoses], w[kDoses];
  float sw = 0.0f, sx = 0.0f, sy = 0.0f;
  std::size_t longest = 0;
  for (std::size_t i = 0; i < count_; ++i) {
    x[i] = std::log(float(entries_[i].open_100us) * kSecondsPerUnit);
    y[i] = std::log(float(entries_[i].final_g));
    if (x[i] > x[longest]) longest = i;
    const float d = (x[i] - x0) / kNearness;
    w[i] = std::exp(-d * d);
    sw += w[i];
    sx += w[i] * x[i];
    sy += w[i] * y[i];
  }
  if (!(sw > kLeastWeight)) return law;
  const float mx = sx / sw, my = sy / sw;
  float sxx = 0.0f, sxy = 0.0f;
  for (std::size_t i = 0; i < count_; ++i) {
    sxx += w[i] * (x[i] - mx) * (x[i] - mx);
    sxy += w[i] * (x[i] - mx) * (y[i] - my);
  }
  float k = sxx > 1e-4f * sw ? sxy / sxx : kPriorK;
  k = k < kLeastK ? kLeastK : (k > kMostK ? kMostK : k);
  if (count_ < kDosesThatTellASlopeBeyond && x0 > x[longest] && k < kOneDoseK) return cube_through(entries_[longest]);
  law.valid = std::isfinite(k) && std::isfinite(my - k * mx);
  law.k = k;
  law.log_a = my - k * mx;
  return law;
}

}  // namespace dynweigh::firmware
