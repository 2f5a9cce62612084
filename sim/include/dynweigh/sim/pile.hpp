#pragma once
// The heap in the container: height of its top from its mass, the angle of repose and the
// container (a cone until its base fills the container, then a cone on a rising cylinder), so the
// fall height h shrinks as the dose grows (thesis §2.1, h~).
//
// With the pile-top component (thesis §2.3.1, fig. 2.4) the stream flattens the apex to a plateau
// of the stream's radius r_f, a truncated cone: V = pi/3 tan(theta) (R^3 - r_f^3), H = tan(theta)
// (R - r_f); and it digs a dent under the stream that deepens to its full depth while the stream
// lands at full rate and fills again when it stops (first order). Both change h, never the mass.
#include <cstdint>

#include "dynweigh/sim/scene.hpp"

namespace dynweigh::sim {

class Pile {
 public:
  // `top` is null when the scene does not run the pile-top component: a sharp cone.
  Pile(const ColumnParameters& column, const PileTopParameters* top, double bulk_density);

  // Height of the (flattened) top above the container floor, without the dent.
  double top_height_m(double mass_kg);
  // Base radius of the heap's slope as a fraction of the container's radius, in [0, 1]: the
  // slope an avalanche runs down grows with it (thesis §3.2).
  double slope_fraction(double mass_kg);
  // Orifice to the top under the stream, never below 1 mm (the pile has reached the orifice).
  double fall_height_m(double mass_kg);

  // Moves the dent toward its depth for a stream landing at `landing_fraction` of full rate.
  void update_dent(double landing_fraction, double dt);
  double dent_m() const { return dent_m_; }

  std::uint64_t steps() const { return steps_; }
  std::uint64_t dent_steps() const { return dent_steps_; }

 private:
  void update_cache(double mass_kg);

  double orifice_to_floor_m_;
  double slope_;            // tan of the repose angle
  double container_radius_m_;
  double flat_radius_m_;
  double bulk_density_;
  double full_volume_m3_;   // truncated cone whose base fills the container
  double dent_depth_m_ = 0.0;
  double dent_settle_s_ = 1.0;
  double dent_m_ = 0.0;
  double cached_dt_ = -1.0;
  double cached_dent_share_ = 0.0;
  double cached_mass_kg_ = -1.0;
  double cached_height_m_ = 0.0;
  double cached_base_radius_m_ = 0.0;
  std::uint64_t steps_ = 0;
  std::uint64_t dent_steps_ = 0;
};

}  // namespace dynweigh::sim
