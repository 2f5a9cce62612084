#pragma once
// The 2D flat-bottom silo of the LAMMPS peer inputs (in.silo2d.fill, in.silo2d.dis), in
// the same reduced (LJ) units: d = 1, g = 1, disc density 1 per area, time in sqrt(d/g).
// Side walls are the planes x = 0 and x = width; the bottom is a row of fixed discs of
// diameter 1 at y = 0, x = 0, 1, .., width; the orifice is opened by removing n of them around
// the middle, which leaves a gap of n d. Moving discs start on a square lattice (spacing 1.12)
// with diameters uniform in [0.9, 1.1]. Optionally a container bottom (the scale) lies
// `container_drop` below the orifice; without it discs below y = -30 leave the box, as in the peer.
#include <cstdint>
#include <vector>

#include "dynweigh/granular/dem2d_world.hpp"

namespace dynweigh::granular {

struct Silo2dConfig {
  double width = 50.0;                // peer: variable W 50
  int moving_discs = 3612;            // peer fill: 43 x 84 lattice sites
  double lattice_spacing = 1.12;      // peer: lattice sq 0.797194
  double fill_min_x = 1.0, fill_max_x = 49.0, fill_min_y = 1.5;  // peer: region fill
  double diameter_min = 0.9, diameter_max = 1.1;                 // peer: 0.9 + 0.2 random
  double wall_disc_diameter = 1.0;
  double density = 1.0;               // peer: density/disc 1 (mass = pi r^2)
  double inertia_factor = 0.4;        // LAMMPS atom_style sphere: I = 0.4 m r^2 even in 2D
  double gravity = 1.0;
  double time_step = 5e-4;            // peer: timestep 5e-4
  double skin = 0.3;                  // peer: neighbor 0.3
  double box_top = 115.0;             // peer: region reg ... -30 115
  double box_bottom = -30.0;
  double container_drop = 0.0;        // > 0: a container bottom wall this far below y = 0
  ContactParameters contact;          // defaults are the peer's kn 2e4, gamma_n 97, mu 0.5
  std::uint64_t seed = 58271;         // peer's seed for the diameters (our own generator)
};

// Builds the closed silo with its discs on the lattice (not yet settled).
Dem2dWorld make_silo2d(const Silo2dConfig& config);
// Opens an orifice of `discs` bottom discs in the middle; returns how many were removed.
std::size_t open_silo2d_orifice(Dem2dWorld& world, const Silo2dConfig& config, int discs);

struct DischargeSample {
  double time = 0;
  std::size_t above = 0;  // moving discs above the bottom (y > 0.5, the peer's v_nab)
};

struct DischargeResult {
  double rate = 0;               // discs per unit time over the whole window (least squares)
  double rate_first_half = 0;    // same over the first and second half of the window, to show
  double rate_second_half = 0;   //   that the rate does not depend on the fill height
  std::int64_t steps = 0;
  double particle_steps = 0;     // sum over steps of the discs in the world
  std::vector<DischargeSample> samples;
};

// Fits the rates of a series of (time, discs above) samples, leaving out the first
// `skip_fraction` of the discharged discs (start-up transient).
void fit_discharge_rates(DischargeResult& result, double skip_fraction);

// Runs the open silo until fewer than `stop_below` discs remain above the bottom (or max_steps),
// sampling every `sample_every` steps. The rate is fitted after the first `skip_fraction` of
// the discharged discs have left (start-up transient).
DischargeResult measure_silo2d_discharge(Dem2dWorld& world, std::size_t stop_below, std::int64_t max_steps,
                                         std::int64_t sample_every, double skip_fraction = 0.1);

// 2D Beverloo law W = C (D - k d)^1.5 fitted through (D, W) by least squares on W^(2/3).
struct BeverlooFit {
  double c = 0;  // in the rate's units per d^1.5
  double k = 0;
  double worst_relative_residual = 0;
};
BeverlooFit fit_beverloo_2d(const std::vector<double>& orifice, const std::vector<double>& rate, double grain_diameter);

}  // namespace dynweigh::granular
