#pragma once
// The scrolling force trace of the live view: the last few seconds of the force on the load cell
// with the valve command beneath it, drawn into a rectangle of the window (OpenGL, pixels).
#include <cstddef>
#include <deque>

namespace dynweigh::tools {

struct Rect {
  float x, y, w, h;  // pixels, origin bottom left
};

class ForceTrace {
 public:
  explicit ForceTrace(double window_s = 10.0) : window_s_(window_s) {}
  void add(double t_s, double force_n, int valve);
  void clear() { samples_.clear(); }
  void draw(const Rect& area) const;
  double latest_force_n() const { return samples_.empty() ? 0.0 : samples_.back().force_n; }

  // Colours the screenshot test looks for: keep them distinct from everything else drawn.
  static constexpr float kForceRgb[3] = {1.0f, 0.82f, 0.0f};
  static constexpr float kValveRgb[3] = {0.2f, 0.85f, 0.35f};

 private:
  struct Sample {
    double t_s, force_n;
    int valve;
  };
  double window_s_;
  std::deque<Sample> samples_;
};

}  // namespace dynweigh::tools
