#pragma once
// The 2D discrete element method (thesis section 3.4, done as Cundall & Strack 1979): soft discs
// with the spring-dashpot contact of dem_contact_parameters.hpp, rotation, fixed wall segments
// and fixed discs, velocity Verlet (as LAMMPS' fix nve/sphere), and a Verlet neighbour list with
// a skin built from a cell list, carrying each contact's tangential history across rebuilds.
//
// Layout: structure of arrays for the per-disc hot data; pairs and wall contacts in flat arrays
// reserved at set-up. step() neither allocates (while the reserved capacity holds) nor throws.
// Contact forces in two passes: a branch-free pass lists the pairs in contact, then their forces
// are computed two at a time in 2-wide SIMD lanes (per-lane scalar arithmetic) and added to the
// discs in list order, so a run is bit-identical whatever the lane width or the skin (and the
// library is built without FMA contraction, so the same on targets that have FMA).
// The second half-kick of a step is done at the start of the next one, in the same pass as that
// step's first half-kick and drift (bit-identical to doing it at the end: the same two roundings
// in the same order); the velocity accessors add the pending half-kick on the fly, and every
// set-up call applies it first.
// Fixed discs (a wall built of discs, as in the peer silo) are never moved; the contact force on
// them and on every wall segment is kept each step: that is the force on the scale.
#include <cstdint>
#include <limits>
#include <vector>

#include "dynweigh/granular/cell_grid.hpp"
#include "dynweigh/granular/dem_contact_parameters.hpp"
#include "dynweigh/granular/wall_segment.hpp"

namespace dynweigh::granular {

struct Dem2dSettings {
  ContactParameters contact;
  double time_step_s = 5e-4;
  double gravity_x = 0.0;
  double gravity_y = -9.81;  // standard gravity; scenes in reduced units set -1
  double skin = 0.3;         // neighbour-list skin (peer: "neighbor 0.3 bin")
  // Domain of the cell list; discs outside are still handled (clamped into border cells).
  double domain_min_x = 0, domain_min_y = 0, domain_max_x = 1, domain_max_y = 1;
  // Moving discs that fall below this height are taken out at the next list rebuild (the
  // peer's fixed box boundary with "lost ignore").
  double remove_below_y = -std::numeric_limits<double>::infinity();
};

struct DiscSpec {
  double x = 0, y = 0;
  double radius = 0.5;
  double mass = 1.0;
  double inertia_factor = 0.5;  // I = factor m r^2: 0.5 for a disc, 0.4 for LAMMPS' spheres
  bool fixed = false;
  double vx = 0, vy = 0, omega = 0;
};

struct Force2 {
  double x = 0, y = 0;
};

class Dem2dWorld {
 public:
  Dem2dWorld(const Dem2dSettings& settings, std::size_t disc_capacity);

  // Set-up.
  std::size_t add_disc(const DiscSpec& disc);
  std::size_t add_wall(const WallSegment& wall);
  // Moves a wall between steps (a slide gate). The larger displacement of its two ends counts as
  // travel toward the next list rebuild, so no contact is missed. The contact force still treats
  // the wall as at rest: its own speed does not enter the damping (a gate, not a piston).
  void move_wall(std::size_t wall, const WallSegment& to);
  const WallSegment& wall(std::size_t index) const { return walls_[index]; }
  // Removes every disc (moving or fixed, as asked) whose centre lies in the box; keeps history.
  std::size_t remove_discs_in_box(double min_x, double max_x, double min_y, double max_y, bool fixed_only);

  // Time stepping.
  void step();
  void run(std::int64_t steps) {
    for (std::int64_t s = 0; s < steps; ++s) step();
  }

  // State.
  const Dem2dSettings& settings() const { return settings_; }
  std::size_t size() const { return count_; }
  std::size_t moving_count() const;
  double time() const { return time_; }
  std::int64_t steps() const { return steps_; }
  std::int64_t removed() const { return removed_; }
  std::int64_t list_rebuilds() const { return rebuilds_; }
  std::size_t pair_count() const { return pairs_.size(); }
  double x(std::size_t i) const { return x_[i]; }
  double y(std::size_t i) const { return y_[i]; }
  double vx(std::size_t i) const { return half_kick_pending_ ? vx_[i] + half_step() * fx_[i] * inv_mass_[i] : vx_[i]; }
  double vy(std::size_t i) const { return half_kick_pending_ ? vy_[i] + half_step() * fy_[i] * inv_mass_[i] : vy_[i]; }
  double omega(std::size_t i) const {
    return half_kick_pending_ ? omega_[i] + half_step() * torque_[i] * inv_inertia_[i] : omega_[i];
  }
  double radius(std::size_t i) const { return radius_[i]; }
  double mass(std::size_t i) const { return mass_[i]; }
  bool fixed(std::size_t i) const { return inv_mass_[i] == 0.0; }
  std::size_t wall_count() const { return walls_.size(); }
  // Contact force the discs exerted on a wall segment / on all fixed discs in the last step.
  Force2 wall_force(std::size_t wall) const { return wall_force_[wall]; }
  Force2 fixed_disc_force() const { return fixed_disc_force_; }
  std::size_t count_moving_above(double y) const;

  // Energies (for the conservation test): kinetic incl. rotation, gravitational relative to
  // y = 0, elastic of the normal and tangential springs of every contact.
  double kinetic_energy() const;
  double potential_energy() const;
  double elastic_energy() const;

 public:
  // A contact candidate of the neighbour list (public only for the force kernel).
  struct Pair {
    std::uint32_t i, j;
    double effective_mass;
    double shear_x, shear_y;  // tangential history s
  };
 private:
  struct WallContact {
    std::uint32_t i, wall;
    double shear_x, shear_y;
  };

  double half_step() const { return 0.5 * settings_.time_step_s; }
  // Applies the pending second half-kick of the last step (before any change of the set-up).
  void finish_half_kick();
  // Kicks (twice if the last step's second half-kick is pending), drifts, and resets the
  // forces to the weights: one pass over the discs.
  void kick_and_drift();
  void compute_forces();
  void rebuild_lists();
  void compact(std::vector<std::int32_t>& new_index);
  void build_pairs();
  void build_wall_contacts();

  Dem2dSettings settings_;
  std::size_t capacity_;
  std::size_t count_ = 0;
  double time_ = 0;
  std::int64_t steps_ = 0;
  std::int64_t removed_ = 0;
  std::int64_t rebuilds_ = 0;
  bool lists_valid_ = false;
  bool half_kick_pending_ = false;
  bool grid_configured_ = false;
  double travel_since_build_ = 0;  // upper bound of any disc's displacement since the last build
  double max_radius_ = 0;

  // Per disc, structure of arrays.
  std::vector<double> x_, y_, vx_, vy_, omega_, fx_, fy_, torque_;
  std::vector<double> radius_, mass_, inv_mass_, inv_inertia_, weight_x_, weight_y_;

  std::vector<WallSegment> walls_;
  std::vector<Force2> wall_force_;
  Force2 fixed_disc_force_;
  std::vector<std::uint32_t> fixed_list_;

  std::vector<Pair> pairs_, old_pairs_;  // sorted by (i, j), i < j
  std::vector<std::uint32_t> touching_;    // indices of the pairs in contact this step (scratch)
  std::vector<WallContact> wall_contacts_, old_wall_contacts_;
  std::vector<std::uint32_t> scratch_;
  std::vector<std::int32_t> new_index_;
  CellGrid grid_;
};

}  // namespace dynweigh::granular
