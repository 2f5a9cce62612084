// The 2D DEM contact against the closed-form linear spring-dashpot results of docs/scenes.md
// section 3, energy conservation without damping, and Cundall-Strack friction with rotation.
#include <gtest/gtest.h>

#include <cmath>

#include "dynweigh/granular/dem2d_world.hpp"

using namespace dynweigh::granular;

namespace {
const double kPi = std::acos(-1.0);

Dem2dSettings free_space(const ContactParameters& contact, double dt) {
  Dem2dSettings s;
  s.contact = contact;
  s.time_step_s = dt;
  s.gravity_y = 0.0;
  s.skin = 0.1;
  s.domain_min_x = -5;
  s.domain_max_x = 5;
  s.domain_min_y = -5;
  s.domain_max_y = 5;
  return s;
}

DiscSpec disc(double x, double y, double vx, double mass, double radius = 0.5) {
  DiscSpec d;
  d.x = x;
  d.y = y;
  d.vx = vx;
  d.mass = mass;
  d.radius = radius;
  return d;
}
}  // namespace

TEST(Dem2dContact, TwoDiscCollisionGivesTheSpringDashpotRestitutionAndDuration) {
  ContactParameters contact;
  contact.normal_stiffness = 1e5;
  const double m1 = 1.0, m2 = 2.0;
  const double meff = m1 * m2 / (m1 + m2);
  for (const double target_e : {0.9, 0.5, 0.2}) {
    contact.normal_damping = normal_damping_for_restitution(target_e, contact.normal_stiffness, meff);
    const double expected_e = restitution_coefficient(contact, meff);
    ASSERT_NEAR(expected_e, target_e, 1e-12);
    const double expected_tc = contact_duration(contact, meff);
    const double dt = expected_tc / 2000;
    Dem2dWorld world(free_space(contact, dt), 2);
    world.add_disc(disc(-0.6, 0.0, 1.0, m1));
    world.add_disc(disc(0.6, 0.0, -0.5, m2));
    const double approach = world.vx(0) - world.vx(1);
    std::int64_t touching_steps = 0;
    bool touched = false;
    for (int s = 0; s < 200000; ++s) {
      world.step();
      const bool touching = world.x(1) - world.x(0) < 1.0;
      touching_steps += touching ? 1 : 0;
      touched = touched || touching;
      if (touched && !touching && touching_steps > 10) break;
    }
    const double separation = world.vx(1) - world.vx(0);
    // The overlap delta(t) = (v/omega) exp(-gamma t / 2) sin(omega t) returns to zero after
    // pi / omega, the closed-form contact time (the damping force may pull for a moment at the
    // end, as in LAMMPS without limit_damping).
    EXPECT_NEAR(separation / approach, expected_e, 0.01 * expected_e) << "e = " << target_e;
    EXPECT_NEAR(static_cast<double>(touching_steps) * dt, expected_tc, 0.01 * expected_tc) << "e = " << target_e;
    // Momentum is kept.
    EXPECT_NEAR(m1 * world.vx(0) + m2 * world.vx(1), m1 * 1.0 - m2 * 0.5, 1e-12);
  }
}

TEST(Dem2dContact, EnergyIsConservedWithoutDamping) {
  ContactParameters contact;
  contact.normal_stiffness = 1e4;
  contact.normal_damping = 0.0;
  contact.tangential_damping = 0.0;
  contact.friction = 0.0;
  const double dt = contact_duration(contact, 0.5) / 5000;
  Dem2dSettings settings = free_space(contact, dt);
  settings.gravity_y = -9.81;
  Dem2dWorld world(settings, 3);
  world.add_wall(WallSegment{-3, -1, 3, -1});
  world.add_wall(WallSegment{-3, -1, -3, 3});
  world.add_wall(WallSegment{3, -1, 3, 3});
  world.add_disc(disc(-1.0, 0.5, 1.5, 1.0));
  world.add_disc(disc(1.0, 0.2, -1.0, 1.0));
  world.add_disc(disc(0.1, 1.6, 0.3, 1.5, 0.4));
  const double initial = world.kinetic_energy() + world.potential_energy() + world.elastic_energy();
  double worst = 0;
  for (int s = 0; s < 400000; ++s) {
    world.step();
    if (s % 1000 == 0) {
      const double e = world.kinetic_energy() + world.potential_energy() + world.elastic_energy();
      worst = std::max(worst, std::fabs(e - initial) / std::fabs(initial));
    }
  }
  EXPECT_GT(world.list_rebuilds(), 1);
  EXPECT_LT(worst, 1e-6);
}

TEST(Dem2dContact, SlidingDiscRollsAtTwoThirdsOfItsSpeed) {
  // A disc (I = m r^2 / 2) launched sliding without spin on a floor: friction slows it and spins
  // it up until it rolls, v = v0 / (1 + I / (m r^2)) = 2/3 v0, omega = -v / r.
  ContactParameters contact;
  contact.normal_stiffness = 1e5;
  contact.tangential_stiffness = 2.0 / 7.0 * 1e5;
  contact.normal_damping = 50;
  contact.tangential_damping = 25;
  contact.friction = 0.3;
  Dem2dSettings settings = free_space(contact, 2e-5);
  settings.gravity_y = -9.81;
  settings.domain_min_x = -1;
  settings.domain_max_x = 20;
  Dem2dWorld world(settings, 1);
  world.add_wall(WallSegment{-1, 0, 20, 0});
  const double r = 0.1;
  DiscSpec d = disc(0.0, r - 9.81 * 1.0 / 1e5, 2.0, 1.0, r);  // resting at its static overlap
  world.add_disc(d);
  world.run(100000);  // 2 s; sliding ends after v0 / (3 mu g) = 0.23 s
  EXPECT_NEAR(world.vx(0), 2.0 * 2.0 / 3.0, 0.01 * 4.0 / 3.0);
  EXPECT_NEAR(world.omega(0) * r, -world.vx(0), 0.01 * world.vx(0));
}

TEST(Dem2dContact, WallsCarryTheWeightOfASettledPile) {
  ContactParameters contact;
  contact.normal_stiffness = 2e5;
  contact.normal_damping = 200;
  contact.tangential_damping = 100;
  Dem2dSettings settings = free_space(contact, 1e-4);
  settings.gravity_y = -9.81;
  settings.domain_min_x = 0;
  settings.domain_max_x = 6;
  settings.domain_min_y = 0;
  settings.domain_max_y = 12;
  Dem2dWorld world(settings, 60);
  const auto bottom = world.add_wall(WallSegment{0, 0, 6, 0});
  const auto left = world.add_wall(WallSegment{0, 0, 0, 12});
  const auto right = world.add_wall(WallSegment{6, 0, 6, 12});
  double weight = 0;
  for (int k = 0; k < 60; ++k) {
    const double radius = 0.25 + 0.02 * (k % 5);
    DiscSpec s = disc(0.6 + 1.2 * (k % 5), 0.6 + 1.1 * (k / 5), 0.0, kPi * radius * radius, radius);
    world.add_disc(s);
    weight += s.mass * 9.81;
  }
  world.run(50000);
  ASSERT_LT(world.kinetic_energy(), 1e-6 * weight);
  // Averaged over 1 s, the pile's momentum change is negligible: the walls carry its weight.
  double carried = 0, on_bottom = 0;
  constexpr int kAveraging = 10000;
  for (int s = 0; s < kAveraging; ++s) {
    world.step();
    carried += world.wall_force(bottom).y + world.wall_force(left).y + world.wall_force(right).y;
    on_bottom += world.wall_force(bottom).y;
  }
  carried /= kAveraging;
  on_bottom /= kAveraging;
  EXPECT_NEAR(-carried, weight, 1e-3 * weight);
  EXPECT_GT(-on_bottom, 0.5 * weight);
}

TEST(Dem2dContact, NeighbourListSkinDoesNotChangeTheResult) {
  // Contacts are evaluated in the same (i, j) order whatever the skin, and their tangential
  // history is carried over each rebuild: a small skin (many rebuilds) and a large one (few)
  // must give bit-identical runs.
  auto run = [](double skin) {
    ContactParameters contact;
    Dem2dSettings settings = free_space(contact, 1e-4);
    settings.gravity_y = -9.81;
    settings.skin = skin;
    settings.domain_min_x = 0;
    settings.domain_max_x = 5;
    settings.domain_min_y = 0;
    settings.domain_max_y = 10;
    Dem2dWorld world(settings, 40);
    world.add_wall(WallSegment{0, 0, 5, 0});
    world.add_wall(WallSegment{0, 0, 0, 10});
    world.add_wall(WallSegment{5, 0, 5, 10});
    for (int k = 0; k < 40; ++k) world.add_disc(disc(0.5 + 1.0 * (k % 4) + 0.1 * (k % 3), 0.6 + 1.05 * (k / 4), 0.3 * ((k % 7) - 3), 0.8, 0.45));
    world.run(20000);
    return world;
  };
  const Dem2dWorld small = run(0.05);
  const Dem2dWorld large = run(0.6);
  ASSERT_GT(small.list_rebuilds(), 3 * large.list_rebuilds());
  for (std::size_t i = 0; i < small.size(); ++i) {
    ASSERT_EQ(small.x(i), large.x(i)) << i;
    ASSERT_EQ(small.y(i), large.y(i)) << i;
    ASSERT_EQ(small.omega(i), large.omega(i)) << i;
  }
}

TEST(Dem2dContact, DeferredHalfKickIsBitIdenticalToFinishingEachStep) {
  // step() leaves the last half-kick pending (done in the next step's pass over the discs);
  // a set-up call in between applies it at once. Both ways must give the same bits, and the
  // velocity accessors must show the finished step either way.
  auto make = [] {
    ContactParameters contact;
    Dem2dSettings settings = free_space(contact, 1e-4);
    settings.gravity_y = -9.81;
    settings.domain_min_x = 0;
    settings.domain_max_x = 5;
    settings.domain_min_y = 0;
    settings.domain_max_y = 10;
    Dem2dWorld world(settings, 41);
    world.add_wall(WallSegment{0, 0, 5, 0});
    world.add_wall(WallSegment{0, 0, 0, 10});
    world.add_wall(WallSegment{5, 0, 5, 10});
    for (int k = 0; k < 40; ++k) world.add_disc(disc(0.5 + 1.0 * (k % 4) + 0.1 * (k % 3), 0.6 + 1.05 * (k / 4), 0.3 * ((k % 7) - 3), 0.8, 0.45));
    return world;
  };
  Dem2dWorld continuous = make();
  Dem2dWorld interrupted = make();
  continuous.run(6000);
  interrupted.run(3000);
  const double vx_before = interrupted.vx(7), omega_before = interrupted.omega(7);
  interrupted.add_wall(WallSegment{4.9, 9.9, 5.0, 10.0});  // far from every disc: finishes the kick
  EXPECT_EQ(interrupted.vx(7), vx_before);
  EXPECT_EQ(interrupted.omega(7), omega_before);
  interrupted.run(3000);
  for (std::size_t i = 0; i < continuous.size(); ++i) {
    ASSERT_EQ(continuous.x(i), interrupted.x(i)) << i;
    ASSERT_EQ(continuous.vy(i), interrupted.vy(i)) << i;
    ASSERT_EQ(continuous.omega(i), interrupted.omega(i)) << i;
  }
}
