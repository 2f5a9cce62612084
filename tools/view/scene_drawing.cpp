#include "scene_drawing.hpp"

#include <SDL_opengl.h>

#include <algorithm>
#include <cmath>

namespace dynweigh::tools {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kSiloDiameterM = 0.30;     // drawn size; the plant has no silo diameter
constexpr double kSiloHeightM = 0.45;
constexpr double kHopperHeightM = 0.15;
constexpr double kContainerHeightM = 0.35;

// Metres of the scene to pixels of the area: the orifice near the top, the floor near the bottom.
struct Scale {
  double cx, floor_y, px_per_m;
  float x(double m) const { return float(cx + m * px_per_m); }
  float y(double m) const { return float(floor_y + m * px_per_m); }
};

void quad(const Scale& s, double x0, double y0, double x1, double y1) {
  glVertex2f(s.x(x0), s.y(y0));
  glVertex2f(s.x(x1), s.y(y0));
  glVertex2f(s.x(x1), s.y(y1));
  glVertex2f(s.x(x0), s.y(y1));
}

}  // namespace

void draw_plant(const sim::Plant& plant, const StreamTimes& times, const Rect& a) {
  const sim::Scene& scene = plant.scene();
  const sim::PlantTruth& truth = plant.truth();
  const double fall_m = scene.column.fall_height_m;
  const double top_m = fall_m + kHopperHeightM + kSiloHeightM;
  const double px_per_m = std::min((a.h - 20.0) / (top_m + 0.05), (a.w - 20.0) / std::max(0.5, scene.column.container_diameter_m + 0.2));
  const Scale s{a.x + a.w / 2.0, a.y + 10.0, px_per_m};
  const double bore = scene.silo.bore_m;
  const double r_silo = kSiloDiameterM / 2.0;
  const double r_box = scene.column.container_diameter_m / 2.0;

  glColor3f(0.07f, 0.08f, 0.10f);  // background
  glBegin(GL_QUADS);
  glVertex2f(a.x, a.y);
  glVertex2f(a.x + a.w, a.y);
  glVertex2f(a.x + a.w, a.y + a.h);
  glVertex2f(a.x, a.y + a.h);
  glEnd();

  // Sand in the silo: the cylinder holds what is left above the hopper.
  const double sand_m3 = std::max(0.0, truth.silo_kg) / scene.silo.bulk_density;
  const double level_m = std::min(kSiloHeightM, sand_m3 / (kPi * r_silo * r_silo));
  const float sand[3] = {0.80f, 0.66f, 0.40f};
  glColor3fv(sand);
  glBegin(GL_QUADS);
  quad(s, -r_silo, fall_m + kHopperHeightM, r_silo, fall_m + kHopperHeightM + level_m);
  glEnd();
  if (truth.silo_kg > 0) {  // the hopper stays full while anything is left
    glBegin(GL_TRIANGLES);
    glVertex2f(s.x(-r_silo), s.y(fall_m + kHopperHeightM));
    glVertex2f(s.x(r_silo), s.y(fall_m + kHopperHeightM));
    glVertex2f(s.x(0), s.y(fall_m));
    glEnd();
  }
  // Silo walls and hopper.
  glColor3f(0.75f, 0.78f, 0.82f);
  glLineWidth(2.0f);
  glBegin(GL_LINE_STRIP);
  glVertex2f(s.x(-r_silo), s.y(top_m));
  glVertex2f(s.x(-r_silo), s.y(fall_m + kHopperHeightM));
  glVertex2f(s.x(-bore / 2), s.y(fall_m));
  glVertex2f(s.x(bore / 2), s.y(fall_m));
  glVertex2f(s.x(r_silo), s.y(fall_m + kHopperHeightM));
  glVertex2f(s.x(r_silo), s.y(top_m));
  glEnd();

  // The valve: a slide under the orifice, red shut, green open, amber between.
  const double stroke = std::clamp(truth.stroke, 0.0, 1.0);
  if (stroke <= 0.0) {
    glColor3f(0.85f, 0.2f, 0.2f);
  } else if (stroke >= 1.0) {
    glColor3f(0.2f, 0.8f, 0.3f);
  } else {
    glColor3f(0.95f, 0.6f, 0.1f);
  }
  glBegin(GL_QUADS);
  quad(s, -bore / 2 - 0.01 - stroke * bore, fall_m - 0.02, bore / 2 + 0.01 - stroke * bore, fall_m);
  glEnd();

  // The pile: a cone at the angle of repose, as high as the plant says the fall has shortened.
  const double pile_m = std::max(0.0, fall_m - truth.fall_height_m);
  if (pile_m > 1e-4 || truth.static_kg > 0) {
    const double slope = std::tan(scene.column.repose_angle_deg * kPi / 180.0);
    const double half_base = std::min(r_box, std::max(pile_m / slope, 0.02));
    glColor3fv(sand);
    glBegin(GL_TRIANGLES);
    glVertex2f(s.x(-half_base), s.y(0));
    glVertex2f(s.x(half_base), s.y(0));
    glVertex2f(s.x(0), s.y(std::max(pile_m, 0.005)));
    glEnd();
  }
  // The stream: from where its tail is to where its front is, as wide as the open bore.
  if (truth.in_flight_kg > 1e-6) {
    const double g = scene.g;
    const double since_open = truth.time_s - times.opened_s;
    const double front_drop = times.opened_s >= 0 ? 0.5 * g * since_open * since_open : truth.fall_height_m;
    const double tail_drop = times.closed_s > times.opened_s ? 0.5 * g * std::pow(truth.time_s - times.closed_s, 2.0) : 0.0;
    const double bottom = std::max(pile_m, fall_m - front_drop);
    const double top = std::max(bottom, fall_m - 0.02 - tail_drop);
    const double half = std::max(0.004, 0.45 * bore * std::max(stroke, 0.3));
    glColor3f(0.88f, 0.74f, 0.46f);
    glBegin(GL_QUADS);
    quad(s, -half, bottom, half, top);
    glEnd();
  }
  // Container and the scale platform under it.
  glColor3f(0.6f, 0.65f, 0.72f);
  glBegin(GL_LINE_STRIP);
  glVertex2f(s.x(-r_box), s.y(kContainerHeightM));
  glVertex2f(s.x(-r_box), s.y(0));
  glVertex2f(s.x(r_box), s.y(0));
  glVertex2f(s.x(r_box), s.y(kContainerHeightM));
  glEnd();
  glBegin(GL_QUADS);
  quad(s, -r_box - 0.05, -0.03, r_box + 0.05, -0.01);
  glEnd();
  glLineWidth(1.0f);
}

}  // namespace dynweigh::tools
