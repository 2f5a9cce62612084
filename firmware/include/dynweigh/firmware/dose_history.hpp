#pragma once
// The last few doses of a material that ran full open from the open command to the close: each its
// open time (command to command) and its certified final. Kept with the material in the settings
// record, power-safe.
//
// Why: the open-time law (learned_fill_law.hpp) is a straight line, fill = a t + b. A dose that
// closes before the valve is fully open, or before the flow has settled, delivers far more than in
// proportion to its open time: the gate's flow grows with its stroke much faster than the stroke
// (model/gate_flow_shape.hpp), and the flow's start-up adds to that. A line fitted to such doses
// predicts too little near and beyond the longest of them, and its close comes late: an overdose
// no top-up takes back. The doses near the open time a close will come at tell the curve: a power law
// fill = A t^k fitted in logarithms, each dose weighted by how near its open time is (a Gaussian of
// kNearness in ln t), k held within [1, 4] (a valve and a stream whose fill grows slower than the
// open time, or faster than the fourth power of it, are none this law has seen). A single dose tells
// no slope: the curve through it grows as the cube of the open time, as a fill does while the gate
// is still opening; the line through that one dose, carried to the next dose's open time, overdosed
// 500 g fills by up to 430 g on the plant family. Two doses tell it badly (each scatters by the
// valve's jitter and the flow's start-up): beyond the longer of two, the curve grows at least as
// the cube. The model cutoff predicts the larger of the line and this curve (model_cutoff.hpp): a
// close the curve times ends short at worst, and a top-up finishes it.
//
// Stored compactly, so that sixteen materials' histories fit the settings record and the Cortex-M's
// RAM: the open time in 0.1 ms (up to 6.5 s) and the final in grams (up to 65 kg). A dose that does
// not fit is left out: such a dose is long, closed on a measured stream, and no close the curve
// guards comes near it.
#include <cstddef>
#include <cstdint>

namespace dynweigh::firmware {

class DoseHistory {
 public:
  static constexpr std::size_t kDoses = 8;
  static constexpr float kNearness = 0.5f;    // the weights' width, in ln t
  static constexpr float kLightestG = 3.0f;    // lighter doses tell no curve (the scale's resolution)

  struct Entry {
    std::uint16_t open_100us = 0;
    std::uint16_t final_g = 0;
  };
  // fill = exp(log_a) t^k near the open time it was fitted at.
  struct PowerLaw {
    bool valid = false;
    float log_a = 0.0f;
    float k = 0.0f;
    float fill_g(float open_s) const;
    // d fill / d t at `open_s`; given the fill there (fill_g(open_s)), without working it out again.
    float growth_g_per_s(float open_s) const { return growth_g_per_s(open_s, fill_g(open_s)); }
    float growth_g_per_s(float open_s, float fill_there_g) const;
  };

  // A certified dose that ran full open for `open_s` and delivered `final_g`: the oldest makes room.
  void add(float open_s, float final_g);
  // The power law near `open_s` (invalid with no dose or none near it; with one, the cube through it;
  // with two, at least the cube beyond the longer).
  PowerLaw near(float open_s) const;
  std::size_t size() const { return count_; }

  // The settings record's view (persistent_settings.cpp); restore() refuses what add() cannot make.
  const Entry& entry(std::size_t i) const { return entries_[i]; }
  std::uint8_t next() const { return next_; }
  bool restore(const Entry (&entries)[kDoses], std::uint8_t count, std::uint8_t next);

 private:
  static PowerLaw cube_through(const Entry& dose);
  Entry entries_[kDoses] = {};
  std::uint8_t count_ = 0;
  std::uint8_t next_ = 0;  // where the next dose goes
};

}  // namespace dynweigh::firmware
