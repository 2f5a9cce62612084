#pragma once
// A fixed straight wall of the 2D DEM (silo side, hopper flank, container bottom): discs touch
// it at the nearest point of the segment, so its ends act as round corners.
namespace dynweigh::granular {

struct WallSegment {
  double ax = 0, ay = 0;  // one end, m
  double bx = 0, by = 0;  // other end, m
};

// Nearest point of the segment to (px, py).
inline void nearest_point_on_segment(const WallSegment& w, double px, double py, double& qx, double& qy) {
  const double ex = w.bx - w.ax;
  const double ey = w.by - w.ay;
  const double length_squared = ex * ex + ey * ey;
  double t = length_squared > 0 ? ((px - w.ax) * ex + (py - w.ay) * ey) / length_squared : 0.0;
  t = t < 0 ? 0 : (t > 1 ? 1 : t);
  qx = w.ax + t * ex;
  qy = w.ay + t * ey;
}

}  // namespace dynweigh::granular
