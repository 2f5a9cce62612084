#include "dynweigh/granular/dem2d_world.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace dynweigh::granular {

namespace {
// Pair lists in 2D: a disc has at most about 6 touching partners and a few more within the skin;
// half lists hold each pair once. Reserving 8 per disc keeps step() free of reallocation.
constexpr std::size_t kPairsPerDiscReserve = 8;
constexpr std::size_t kWallContactsPerDiscReserve = 2;
}  // namespace

Dem2dWorld::Dem2dWorld(const Dem2dSettings& settings, std::size_t disc_capacity)
    : settings_(settings), capacity_(disc_capacity) {
  if (!(settings.time_step_s > 0)) throw std::invalid_argument("DEM time step must be positive");
  if (!(settings.skin >= 0)) throw std::invalid_argument("DEM skin must not be negative");
  for (auto* v : {&x_, &y_, &vx_, &vy_, &omega_, &fx_, &fy_, &torque_, &radius_, &mass_, &inv_mass_,
                  &inv_inertia_, &weight_x_, &weight_y_}) {
    v->reserve(disc_capacity);
  }
  pairs_.reserve(disc_capacity * kPairsPerDiscReserve);
  old_pairs_.reserve(disc_capacity * kPairsPerDiscReserve);
  wall_contacts_.reserve(disc_capacity * kWallContactsPerDiscReserve + 16);
  old_wall_contacts_.reserve(disc_capacity * kWallContactsPerDiscReserve + 16);
  scratch_.reserve(256);
  first_pair_.reserve(disc_capacity + 1);
  new_index_.reserve(disc_capacity);
  fixed_list_.reserve(disc_capacity);
}

std::size_t Dem2dWorld::add_disc(const DiscSpec& d) {
  if (count_ >= capacity_) throw std::length_error("DEM disc capacity exceeded");
  if (!(d.radius > 0) || !(d.mass > 0)) throw std::invalid_argument("disc radius and mass must be positive");
  x_.push_back(d.x);
  y_.push_back(d.y);
  vx_.push_back(d.fixed ? 0.0 : d.vx);
  vy_.push_back(d.fixed ? 0.0 : d.vy);
  omega_.push_back(d.fixed ? 0.0 : d.omega);
  radius_.push_back(d.radius);
  mass_.push_back(d.mass);
  inv_mass_.push_back(d.fixed ? 0.0 : 1.0 / d.mass);
  inv_inertia_.push_back(d.fixed ? 0.0 : 1.0 / (d.inertia_factor * d.mass * d.radius * d.radius));
  weight_x_.push_back(d.fixed ? 0.0 : d.mass * settings_.gravity_x);
  weight_y_.push_back(d.fixed ? 0.0 : d.mass * settings_.gravity_y);
  fx_.push_back(weight_x_.back());
  fy_.push_back(weight_y_.back());
  torque_.push_back(0.0);
  if (d.fixed) fixed_list_.push_back(static_cast<std::uint32_t>(count_));
  max_radius_ = std::max(max_radius_, d.radius);
  lists_valid_ = false;
  grid_configured_ = false;
  return count_++;
}

std::size_t Dem2dWorld::add_wall(const WallSegment& wall) {
  walls_.push_back(wall);
  wall_force_.push_back(Force2{});
  lists_valid_ = false;
  return walls_.size() - 1;
}

std::size_t Dem2dWorld::moving_count() const { return count_ - fixed_list_.size(); }

std::size_t Dem2dWorld::count_moving_above(double level) const {
  std::size_t n = 0;
  for (std::size_t i = 0; i < count_; ++i) n += (inv_mass_[i] > 0 && y_[i] > level) ? 1 : 0;
  return n;
}

std::size_t Dem2dWorld::remove_discs_in_box(double min_x, double max_x, double min_y, double max_y, bool fixed_only) {
  new_index_.assign(count_, 0);
  std::int32_t next = 0;
  std::size_t removed = 0;
  for (std::size_t i = 0; i < count_; ++i) {
    const bool inside = x_[i] >= min_x && x_[i] <= max_x && y_[i] >= min_y && y_[i] <= max_y;
    if (inside && (!fixed_only || inv_mass_[i] == 0.0)) {
      new_index_[i] = -1;
      ++removed;
    } else {
      new_index_[i] = next++;
    }
  }
  if (removed > 0) {
    compact(new_index_);
    lists_valid_ = false;
  }
  return removed;
}

// Moves the kept discs down over the removed ones, in order, and renumbers the contact lists;
// because the order is kept, the lists stay sorted.
void Dem2dWorld::compact(std::vector<std::int32_t>& new_index) {
  for (auto* v : {&x_, &y_, &vx_, &vy_, &omega_, &fx_, &fy_, &torque_, &radius_, &mass_, &inv_mass_,
                  &inv_inertia_, &weight_x_, &weight_y_}) {
    auto& a = *v;
    for (std::size_t i = 0; i < count_; ++i) {
      if (new_index[i] >= 0) a[static_cast<std::size_t>(new_index[i])] = a[i];
    }
  }
  std::size_t kept = 0;
  for (std::size_t i = 0; i < count_; ++i) kept += new_index[i] >= 0 ? 1 : 0;
  for (auto* v : {&x_, &y_, &vx_, &vy_, &omega_, &fx_, &fy_, &torque_, &radius_, &mass_, &inv_mass_,
                  &inv_inertia_, &weight_x_, &weight_y_}) {
    v->resize(kept);
  }
  removed_ += static_cast<std::int64_t>(count_ - kept);
  count_ = kept;
  std::size_t out = 0;
  for (const Pair& p : pairs_) {
    const std::int32_t i = new_index[p.i], j = new_index[p.j];
    if (i < 0 || j < 0) continue;
    Pair q = p;
    q.i = static_cast<std::uint32_t>(i);
    q.j = static_cast<std::uint32_t>(j);
    pairs_[out++] = q;
  }
  pairs_.resize(out);
  out = 0;
  for (const WallContact& c : wall_contacts_) {
    const std::int32_t i = new_index[c.i];
    if (i < 0) continue;
    WallContact q = c;
    q.i = static_cast<std::uint32_t>(i);
    wall_contacts_[out++] = q;
  }
  wall_contacts_.resize(out);
  fixed_list_.clear();
  for (std::size_t i = 0; i < count_; ++i) {
    if (inv_mass_[i] == 0.0) fixed_list_.push_back(static_cast<std::uint32_t>(i));
  }
}

void Dem2dWorld::rebuild_lists() {
  ++rebuilds_;
  if (std::isfinite(settings_.remove_below_y)) {
    bool any = false;
    for (std::size_t i = 0; i < count_; ++i) {
      if (inv_mass_[i] > 0 && y_[i] < settings_.remove_below_y) {
        any = true;
        break;
      }
    }
    if (any) {
      new_index_.assign(count_, 0);
      std::int32_t next = 0;
      for (std::size_t i = 0; i < count_; ++i) {
        new_index_[i] = (inv_mass_[i] > 0 && y_[i] < settings_.remove_below_y) ? -1 : next++;
      }
      compact(new_index_);
    }
  }
  if (!grid_configured_) {
    grid_.configure(settings_.domain_min_x, settings_.domain_min_y, settings_.domain_max_x, settings_.domain_max_y,
                    2.0 * max_radius_ + settings_.skin, capacity_);
    grid_configured_ = true;
  }
  grid_.build(x_.data(), y_.data(), count_);
  std::swap(pairs_, old_pairs_);
  pairs_.clear();
  build_pairs();
  std::swap(wall_contacts_, old_wall_contacts_);
  wall_contacts_.clear();
  build_wall_contacts();
  travel_since_build_ = 0;
  lists_valid_ = true;
}

void Dem2dWorld::build_pairs() {
  const double skin = settings_.skin;
  const std::uint32_t* items = grid_.items();
  std::size_t old = 0;
  first_pair_.assign(count_ + 1, 0);
  for (std::size_t i = 0; i < count_; ++i) {
    first_pair_[i] = static_cast<std::uint32_t>(pairs_.size());
    const int cx = grid_.cell_x_of(x_[i]);
    const int cy = grid_.cell_y_of(y_[i]);
    const bool i_fixed = inv_mass_[i] == 0.0;
    scratch_.clear();
    for (int ny = std::max(0, cy - 1); ny <= std::min(grid_.cells_y() - 1, cy + 1); ++ny) {
      for (int nx = std::max(0, cx - 1); nx <= std::min(grid_.cells_x() - 1, cx + 1); ++nx) {
        for (std::uint32_t k = grid_.begin(nx, ny); k < grid_.end(nx, ny); ++k) {
          const std::uint32_t j = items[k];
          if (j <= i) continue;
          if (i_fixed && inv_mass_[j] == 0.0) continue;  // two fixed discs never interact
          const double dx = x_[i] - x_[j];
          const double dy = y_[i] - y_[j];
          const double reach = radius_[i] + radius_[j] + skin;
          if (dx * dx + dy * dy < reach * reach) scratch_.push_back(j);
        }
      }
    }
    std::sort(scratch_.begin(), scratch_.end());
    for (const std::uint32_t j : scratch_) {
      Pair p{static_cast<std::uint32_t>(i), j, mass_[i] * mass_[j] / (mass_[i] + mass_[j]), 0.0, 0.0};
      // Carry the tangential history over: both lists are sorted by (i, j).
      while (old < old_pairs_.size() &&
             (old_pairs_[old].i < p.i || (old_pairs_[old].i == p.i && old_pairs_[old].j < p.j))) {
        ++old;
      }
      if (old < old_pairs_.size() && old_pairs_[old].i == p.i && old_pairs_[old].j == p.j) {
        p.shear_x = old_pairs_[old].shear_x;
        p.shear_y = old_pairs_[old].shear_y;
      }
      pairs_.push_back(p);
    }
  }
  first_pair_[count_] = static_cast<std::uint32_t>(pairs_.size());
}

void Dem2dWorld::build_wall_contacts() {
  std::size_t old = 0;
  for (std::size_t i = 0; i < count_; ++i) {
    if (inv_mass_[i] == 0.0) continue;
    for (std::size_t w = 0; w < walls_.size(); ++w) {
      double qx, qy;
      nearest_point_on_segment(walls_[w], x_[i], y_[i], qx, qy);
      const double dx = x_[i] - qx;
      const double dy = y_[i] - qy;
      const double reach = radius_[i] + settings_.skin;
      if (dx * dx + dy * dy >= reach * reach) continue;
      WallContact c{static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(w), 0.0, 0.0};
      while (old < old_wall_contacts_.size() &&
             (old_wall_contacts_[old].i < c.i || (old_wall_contacts_[old].i == c.i && old_wall_contacts_[old].wall < c.wall))) {
        ++old;
      }
      if (old < old_wall_contacts_.size() && old_wall_contacts_[old].i == c.i && old_wall_contacts_[old].wall == c.wall) {
        c.shear_x = old_wall_contacts_[old].shear_x;
        c.shear_y = old_wall_contacts_[old].shear_y;
      }
      wall_contacts_.push_back(c);
    }
  }
}

namespace {
// Tangential part of the Cundall-Strack contact, as LAMMPS gran/hooke/history: accumulate the
// tangential displacement, keep it in the tangent plane, and cap the force at mu |F_n| by
// rescaling the history (so the spring holds exactly the sliding force).
struct TangentialResult {
  double fx, fy;
};
inline TangentialResult tangential_force(double& sx, double& sy, double vtx, double vty, double nx, double ny,
                                         double fn, double meff, const ContactParameters& c, double dt) {
  sx += vtx * dt;
  sy += vty * dt;
  const double sn = sx * nx + sy * ny;
  sx -= sn * nx;
  sy -= sn * ny;
  const double damp = meff * c.tangential_damping;
  double ftx = -(c.tangential_stiffness * sx + damp * vtx);
  double fty = -(c.tangential_stiffness * sy + damp * vty);
  const double ft2 = ftx * ftx + fty * fty;
  const double limit = c.friction * std::fabs(fn);
  if (ft2 > limit * limit) {
    const double ratio = limit / std::sqrt(ft2);
    const double lag = damp / c.tangential_stiffness;
    sx = ratio * (sx + lag * vtx) - lag * vtx;
    sy = ratio * (sy + lag * vty) - lag * vty;
    ftx *= ratio;
    fty *= ratio;
  }
  return {ftx, fty};
}
}  // namespace

void Dem2dWorld::compute_forces() {
  const ContactParameters& c = settings_.contact;
  const double dt = settings_.time_step_s;
  const double kn = c.normal_stiffness;
  const double gn = c.normal_damping;
  double* __restrict fx = fx_.data();
  double* __restrict fy = fy_.data();
  double* __restrict tq = torque_.data();
  const double* __restrict x = x_.data();
  const double* __restrict y = y_.data();
  const double* __restrict vx = vx_.data();
  const double* __restrict vy = vy_.data();
  const double* __restrict w = omega_.data();
  const double* __restrict r = radius_.data();
  for (std::size_t i = 0; i < count_; ++i) {
    fx[i] = weight_x_[i];
    fy[i] = weight_y_[i];
    tq[i] = 0.0;
  }
  // Pairs are grouped by their first disc: its force and torque are summed in registers and
  // stored once, so consecutive pairs do not wait on each other's stores to disc i.
  Pair* __restrict pairs = pairs_.data();
  for (std::size_t i = 0; i < count_; ++i) {
    const std::uint32_t begin = first_pair_[i], end = first_pair_[i + 1];
    if (begin == end) continue;
    const double xi = x[i], yi = y[i], vxi = vx[i], vyi = vy[i], rwi = r[i] * w[i], ri = r[i];
    double fxi = 0, fyi = 0, tqi = 0;
    for (std::uint32_t k = begin; k < end; ++k) {
      Pair& p = pairs[k];
      const std::uint32_t j = p.j;
      const double dx = xi - x[j];
      const double dy = yi - y[j];
      const double rsq = dx * dx + dy * dy;
      const double radsum = ri + r[j];
      if (rsq >= radsum * radsum) {
        p.shear_x = 0.0;  // out of contact: the history ends (as LAMMPS)
        p.shear_y = 0.0;
        continue;
      }
      const double dist = std::sqrt(rsq);
      const double inv = 1.0 / dist;
      const double nx = dx * inv, ny = dy * inv;  // from j to i
      const double vrx = vxi - vx[j];
      const double vry = vyi - vy[j];
      const double vn = vrx * nx + vry * ny;
      // Relative velocity of the contact points: v_i - v_j - (r_i w_i + r_j w_j) (z x n).
      const double spin = rwi + r[j] * w[j];
      const double vtx = vrx - vn * nx + spin * ny;
      const double vty = vry - vn * ny - spin * nx;
      const double fn = kn * (radsum - dist) - p.effective_mass * gn * vn;
      const TangentialResult ft = tangential_force(p.shear_x, p.shear_y, vtx, vty, nx, ny, fn, p.effective_mass, c, dt);
      const double fxx = fn * nx + ft.fx;
      const double fyy = fn * ny + ft.fy;
      fxi += fxx;
      fyi += fyy;
      fx[j] -= fxx;
      fy[j] -= fyy;
      const double cross = nx * ft.fy - ny * ft.fx;  // (n x F_t)_z
      tqi -= ri * cross;
      tq[j] -= r[j] * cross;
    }
    fx[i] += fxi;
    fy[i] += fyi;
    tq[i] += tqi;
  }
  for (auto& f : wall_force_) f = Force2{};
  for (WallContact& wc : wall_contacts_) {
    const std::uint32_t i = wc.i;
    double qx, qy;
    nearest_point_on_segment(walls_[wc.wall], x[i], y[i], qx, qy);
    const double dx = x[i] - qx;
    const double dy = y[i] - qy;
    const double rsq = dx * dx + dy * dy;
    if (rsq >= r[i] * r[i] || rsq == 0.0) {
      wc.shear_x = 0.0;
      wc.shear_y = 0.0;
      continue;
    }
    const double dist = std::sqrt(rsq);
    const double nx = dx / dist, ny = dy / dist;
    const double meff = mass_[i];  // the wall is immovable
    const double vn = vx[i] * nx + vy[i] * ny;
    const double spin = r[i] * w[i];
    const double vtx = vx[i] - vn * nx + spin * ny;
    const double vty = vy[i] - vn * ny - spin * nx;
    const double fn = kn * (r[i] - dist) - meff * gn * vn;
    const TangentialResult ft = tangential_force(wc.shear_x, wc.shear_y, vtx, vty, nx, ny, fn, meff, c, dt);
    const double fxx = fn * nx + ft.fx;
    const double fyy = fn * ny + ft.fy;
    fx[i] += fxx;
    fy[i] += fyy;
    tq[i] -= r[i] * (nx * ft.fy - ny * ft.fx);
    wall_force_[wc.wall].x -= fxx;
    wall_force_[wc.wall].y -= fyy;
  }
  fixed_disc_force_ = Force2{};
  for (const std::uint32_t k : fixed_list_) {
    fixed_disc_force_.x += fx[k];
    fixed_disc_force_.y += fy[k];
  }
}

void Dem2dWorld::half_kick() {
  const double h = 0.5 * settings_.time_step_s;
  for (std::size_t i = 0; i < count_; ++i) {
    vx_[i] += h * fx_[i] * inv_mass_[i];
    vy_[i] += h * fy_[i] * inv_mass_[i];
    omega_[i] += h * torque_[i] * inv_inertia_[i];
  }
}

void Dem2dWorld::drift() {
  const double dt = settings_.time_step_s;
  double fastest_squared = 0;
  for (std::size_t i = 0; i < count_; ++i) {
    x_[i] += dt * vx_[i];
    y_[i] += dt * vy_[i];
    fastest_squared = std::max(fastest_squared, vx_[i] * vx_[i] + vy_[i] * vy_[i]);
  }
  travel_since_build_ += std::sqrt(fastest_squared) * dt;
}

void Dem2dWorld::step() {
  if (!lists_valid_) rebuild_lists();
  // Velocity Verlet: the forces of the previous step are in fx_, fy_, torque_.
  half_kick();
  drift();
  // Two discs approach each other by at most twice the longest travel: rebuild before the skin
  // could be crossed.
  if (2.0 * travel_since_build_ > settings_.skin) rebuild_lists();
  compute_forces();
  half_kick();
  ++steps_;
  time_ += settings_.time_step_s;
}

double Dem2dWorld::kinetic_energy() const {
  double e = 0;
  for (std::size_t i = 0; i < count_; ++i) {
    if (inv_mass_[i] == 0.0) continue;
    e += 0.5 * mass_[i] * (vx_[i] * vx_[i] + vy_[i] * vy_[i]) + 0.5 * omega_[i] * omega_[i] / inv_inertia_[i];
  }
  return e;
}

double Dem2dWorld::potential_energy() const {
  double e = 0;
  for (std::size_t i = 0; i < count_; ++i) e -= weight_x_[i] * x_[i] + weight_y_[i] * y_[i];
  return e;
}

double Dem2dWorld::elastic_energy() const {
  const ContactParameters& c = settings_.contact;
  double e = 0;
  for (const Pair& p : pairs_) {
    const double dx = x_[p.i] - x_[p.j];
    const double dy = y_[p.i] - y_[p.j];
    const double overlap = radius_[p.i] + radius_[p.j] - std::sqrt(dx * dx + dy * dy);
    if (overlap <= 0) continue;
    e += 0.5 * c.normal_stiffness * overlap * overlap +
         0.5 * c.tangential_stiffness * (p.shear_x * p.shear_x + p.shear_y * p.shear_y);
  }
  for (const WallContact& wc : wall_contacts_) {
    double qx, qy;
    nearest_point_on_segment(walls_[wc.wall], x_[wc.i], y_[wc.i], qx, qy);
    const double overlap = radius_[wc.i] - std::hypot(x_[wc.i] - qx, y_[wc.i] - qy);
    if (overlap <= 0) continue;
    e += 0.5 * c.normal_stiffness * overlap * overlap +
         0.5 * c.tangential_stiffness * (wc.shear_x * wc.shear_x + wc.shear_y * wc.shear_y);
  }
  return e;
}

}  // namespace dynweigh::granular
