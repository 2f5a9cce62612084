#include "force_trace.hpp"

#include <SDL_opengl.h>

#include <algorithm>
#include <cmath>

namespace dynweigh::tools {
namespace {

// A round grid step (1, 2 or 5 times a power of ten) that gives about `lines` lines over `span`.
double grid_step(double span, double lines) {
  const double raw = span / lines;
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0}) {
    if (m * power >= raw) return m * power;
  }
  return 10.0 * power;
}

void vertex(double x, double y) { glVertex2f(float(x), float(y)); }

}  // namespace

void ForceTrace::add(double t_s, double force_n, int valve) {
  samples_.push_back({t_s, force_n, valve});
  while (!samples_.empty() && samples_.front().t_s < t_s - window_s_) samples_.pop_front();
}

void ForceTrace::draw(const Rect& a) const {
  // Frame.
  glColor3f(0.10f, 0.12f, 0.15f);
  glBegin(GL_QUADS);
  vertex(a.x, a.y);
  vertex(a.x + a.w, a.y);
  vertex(a.x + a.w, a.y + a.h);
  vertex(a.x, a.y + a.h);
  glEnd();
  if (samples_.empty()) return;

  const double t_end = std::max(window_s_, samples_.back().t_s);
  const double t_begin = t_end - window_s_;
  double f_min = -1.0, f_max = 10.0;
  for (const Sample& s : samples_) {
    f_min = std::min(f_min, s.force_n);
    f_max = std::max(f_max, s.force_n);
  }
  f_max += 0.1 * (f_max - f_min);
  // The lower fifth of the area is the valve strip; the force gets the rest.
  const double valve_h = 0.18 * a.h;
  const double fy0 = a.y + valve_h + 6.0, fh = a.h - valve_h - 12.0;
  const auto px = [&](double t) { return a.x + (t - t_begin) / window_s_ * a.w; };
  const auto py = [&](double f) { return fy0 + (f - f_min) / (f_max - f_min) * fh; };

  // Grid: every second, and round forces.
  glColor3f(0.22f, 0.25f, 0.30f);
  glBegin(GL_LINES);
  for (double t = std::ceil(t_begin); t <= t_end; t += 1.0) {
    vertex(px(t), a.y);
    vertex(px(t), a.y + a.h);
  }
  const double step = grid_step(f_max - f_min, 6.0);
  for (double f = std::ceil(f_min / step) * step; f <= f_max; f += step) {
    vertex(a.x, py(f));
    vertex(a.x + a.w, py(f));
  }
  glEnd();
  glColor3f(0.45f, 0.48f, 0.55f);  // zero force
  glBegin(GL_LINES);
  vertex(a.x, py(0.0));
  vertex(a.x + a.w, py(0.0));
  glEnd();

  // Valve: a step trace in its strip, and a marker line through the force at each change.
  glColor3fv(kValveRgb);
  glLineWidth(2.0f);
  glBegin(GL_LINE_STRIP);
  for (const Sample& s : samples_) vertex(px(s.t_s), a.y + 4.0 + s.valve / 2.0 * (valve_h - 8.0));
  glEnd();
  glLineWidth(1.0f);
  glBegin(GL_LINES);
  for (std::size_t i = 1; i < samples_.size(); ++i) {
    if (samples_[i].valve != samples_[i - 1].valve) {
      vertex(px(samples_[i].t_s), a.y);
      vertex(px(samples_[i].t_s), a.y + a.h);
    }
  }
  glEnd();

  // The force.
  glColor3fv(kForceRgb);
  glLineWidth(2.0f);
  glBegin(GL_LINE_STRIP);
  for (const Sample& s : samples_) vertex(px(s.t_s), py(s.force_n));
  glEnd();
  glLineWidth(1.0f);
}

}  // namespace dynweigh::tools
