#include "dynweigh/granular/dem2d_world.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace dynweigh::granular {

namespace {
// Pair lists in 2D: a disc has at most about 6 touching partners and a few more within the skin;
// half lists hold each pair once. Reserving 8 per disc keeps step() free of reallocation.
constexpr std::size_t kPairsPerDiscReserve = 8;
constexpr std::size_t kWallContactsPerDiscReserve = 2;
// Discs within reach of one disc: 9 cells of at least one reach each hold far fewer than this
// (dense packing of the smallest discs), so the candidate buffer never overflows in practice.
constexpr std::size_t kNeighbourCandidatesMax = 1024;
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
  touching_.reserve(disc_capacity * kPairsPerDiscReserve);
  old_pairs_.reserve(disc_capacity * kPairsPerDiscReserve);
  wall_contacts_.reserve(disc_capacity * kWallContactsPerDiscReserve + 16);
  old_wall_contacts_.reserve(disc_capacity * kWallContactsPerDiscReserve + 16);
  scratch_.assign(kNeighbourCandidatesMax, 0);
  new_index_.reserve(disc_capacity);
  fixed_list_.reserve(disc_capacity);
}

std::size_t Dem2dWorld::add_disc(const DiscSpec& d) {
  if (count_ >= capacity_) throw std::length_error("DEM disc capacity exceeded");
  if (!(d.radius > 0) || !(d.mass > 0)) throw std::invalid_argument("disc radius and mass must be positive");
  finish_half_kick();
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
  finish_half_kick();
  walls_.push_back(wall);
  wall_force_.push_back(Force2{});
  lists_valid_ = false;
  return walls_.size() - 1;
}

void Dem2dWorld::move_wall(std::size_t index, const WallSegment& to) {
  const WallSegment& from = walls_[index];
  const double shift = std::max(std::hypot(to.ax - from.ax, to.ay - from.ay), std::hypot(to.bx - from.bx, to.by - from.by));
  walls_[index] = to;
  travel_since_build_ += shift;
}

std::size_t Dem2dWorld::moving_count() const { return count_ - fixed_list_.size(); }

std::size_t Dem2dWorld::count_moving_above(double level) const {
  std::size_t n = 0;
  for (std::size_t i = 0; i < count_; ++i) n += (inv_mass_[i] > 0 && y_[i] > level) ? 1 : 0;
  return n;
}

std::size_t Dem2dWorld::remove_discs_in_box(double min_x, double max_x, double min_y, double max_y, bool fixed_only) {
  finish_half_kick();
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
  touching_.resize(pairs_.size());  // within the capacity reserved at set-up
  std::swap(wall_contacts_, old_wall_contacts_);
  wall_contacts_.clear();
  build_wall_contacts();
  travel_since_build_ = 0;
  lists_valid_ = true;
}

void Dem2dWorld::build_pairs() {
  const double skin = settings_.skin;
  const std::uint32_t* items = grid_.items();
  const double* __restrict x = x_.data();
  const double* __restrict y = y_.data();
  const double* __restrict r = radius_.data();
  const double* __restrict inv_mass = inv_mass_.data();
  const int cells_x = grid_.cells_x(), cells_y = grid_.cells_y();
  std::size_t old = 0;
  for (std::size_t i = 0; i < count_; ++i) {
    const int cell = static_cast<int>(grid_.cell_of(i));
    const int cx = cell % cells_x, cy = cell / cells_x;
    const bool i_fixed = inv_mass[i] == 0.0;
    const double xi = x[i], yi = y[i], reach_i = r[i] + skin;
    std::size_t found = 0;
    std::uint32_t* candidates = scratch_.data();
    for (int ny = std::max(0, cy - 1); ny <= std::min(cells_y - 1, cy + 1); ++ny) {
      for (int nx = std::max(0, cx - 1); nx <= std::min(cells_x - 1, cx + 1); ++nx) {
        // Items of a cell are ascending: walk down from the top while j > i.
        const std::uint32_t first = grid_.begin(nx, ny);
        for (std::uint32_t k = grid_.end(nx, ny); k > first; --k) {
          const std::uint32_t j = items[k - 1];
          if (j <= i) break;
          const double dx = xi - x[j];
          const double dy = yi - y[j];
          const double reach = reach_i + r[j];
          const bool near = dx * dx + dy * dy < reach * reach && !(i_fixed && inv_mass[j] == 0.0);
          candidates[found] = j;  // two fixed discs never interact
          found += near ? 1 : 0;
          if (found == scratch_.size()) {  // only for extreme size ratios: grow, never overflow
            scratch_.resize(2 * scratch_.size());
            candidates = scratch_.data();
          }
        }
      }
    }
    // Insertion sort: a handful of candidates.
    for (std::size_t a = 1; a < found; ++a) {
      const std::uint32_t v = candidates[a];
      std::size_t b = a;
      for (; b > 0 && candidates[b - 1] > v; --b) candidates[b] = candidates[b - 1];
      candidates[b] = v;
    }
    if (pairs_.size() + found > pairs_.capacity()) pairs_.reserve(2 * pairs_.capacity() + found);  // not in steady state
    for (std::size_t a = 0; a < found; ++a) {
      const std::uint32_t j = candidates[a];
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
// The constants are copied into a local struct so the stores to the history (doubles) cannot
// be taken to alias them.
struct TangentialConstants {
  double stiffness, damping, friction, dt;
};
struct TangentialResult {
  double fx, fy;
};
inline TangentialResult tangential_force(double& shear_x, double& shear_y, double vtx, double vty, double nx, double ny,
                                         double fn, double meff, const TangentialConstants& c) {
  double sx = shear_x + vtx * c.dt;
  double sy = shear_y + vty * c.dt;
  const double sn = sx * nx + sy * ny;
  sx -= sn * nx;
  sy -= sn * ny;
  const double damp = meff * c.damping;
  double ftx = -(c.stiffness * sx + damp * vtx);
  double fty = -(c.stiffness * sy + damp * vty);
  const double ft2 = ftx * ftx + fty * fty;
  const double limit = c.friction * std::fabs(fn);
  if (ft2 > limit * limit) {
    const double ratio = limit / std::sqrt(ft2);
    const double lag = damp / c.stiffness;
    sx = ratio * (sx + lag * vtx) - lag * vtx;
    sy = ratio * (sy + lag * vty) - lag * vty;
    ftx *= ratio;
    fty *= ratio;
  }
  shear_x = sx;
  shear_y = sy;
  return {ftx, fty};
}

// Two contacts at once, one per lane of a 2-wide vector of doubles (GCC/Clang vector
// extensions: SSE2 on x86-64, NEON on AArch64, plain scalar code elsewhere). Every lane does
// exactly the arithmetic of the scalar contact (same operations, same order; sliding is chosen
// per lane by a select), so the results are those of the scalar code on any target.
using Lane2 = double __attribute__((vector_size(16)));
using Mask2 = std::int64_t __attribute__((vector_size(16)));

inline Lane2 lane_sqrt(Lane2 a) {
#if defined(__SSE2__)
  return _mm_sqrt_pd(a);
#else
  return Lane2{std::sqrt(a[0]), std::sqrt(a[1])};
#endif
}

inline Lane2 lane_abs(Lane2 a) {
  const Mask2 no_sign = {0x7fffffffffffffffLL, 0x7fffffffffffffffLL};
  return reinterpret_cast<Lane2>(reinterpret_cast<Mask2>(a) & no_sign);
}

struct PairLaneConstants {
  double kn, gn;
  TangentialConstants tangential;
};

struct PairLaneForces {
  Lane2 fx, fy, torque_i, torque_j, shear_x, shear_y;
};

inline PairLaneForces pair_lane_forces(const Dem2dWorld::Pair& p0, const Dem2dWorld::Pair& p1, const double* __restrict x,
                                       const double* __restrict y, const double* __restrict vx, const double* __restrict vy,
                                       const double* __restrict w, const double* __restrict r, const PairLaneConstants& c) {
  const std::uint32_t i0 = p0.i, j0 = p0.j, i1 = p1.i, j1 = p1.j;
  const Lane2 ri = {r[i0], r[i1]};
  const Lane2 rj = {r[j0], r[j1]};
  const Lane2 dx = Lane2{x[i0], x[i1]} - Lane2{x[j0], x[j1]};
  const Lane2 dy = Lane2{y[i0], y[i1]} - Lane2{y[j0], y[j1]};
  const Lane2 rsq = dx * dx + dy * dy;
  const Lane2 radsum = ri + rj;
  const Lane2 dist = lane_sqrt(rsq);
  const Lane2 inv = 1.0 / dist;
  const Lane2 nx = dx * inv, ny = dy * inv;  // from j to i
  const Lane2 vrx = Lane2{vx[i0], vx[i1]} - Lane2{vx[j0], vx[j1]};
  const Lane2 vry = Lane2{vy[i0], vy[i1]} - Lane2{vy[j0], vy[j1]};
  const Lane2 vn = vrx * nx + vry * ny;
  // Relative velocity of the contact points: v_i - v_j - (r_i w_i + r_j w_j) (z x n).
  const Lane2 spin = ri * Lane2{w[i0], w[i1]} + rj * Lane2{w[j0], w[j1]};
  const Lane2 vtx = vrx - vn * nx + spin * ny;
  const Lane2 vty = vry - vn * ny - spin * nx;
  const Lane2 meff = {p0.effective_mass, p1.effective_mass};
  const Lane2 fn = c.kn * (radsum - dist) - meff * c.gn * vn;
  // Tangential: as tangential_force().
  const TangentialConstants& t = c.tangential;
  Lane2 sx = Lane2{p0.shear_x, p1.shear_x} + vtx * t.dt;
  Lane2 sy = Lane2{p0.shear_y, p1.shear_y} + vty * t.dt;
  const Lane2 sn = sx * nx + sy * ny;
  sx -= sn * nx;
  sy -= sn * ny;
  const Lane2 damp = meff * t.damping;
  Lane2 ftx = -(t.stiffness * sx + damp * vtx);
  Lane2 fty = -(t.stiffness * sy + damp * vty);
  const Lane2 ft2 = ftx * ftx + fty * fty;
  const Lane2 limit = t.friction * lane_abs(fn);
  const Mask2 sliding = ft2 > limit * limit;
  const Lane2 ratio = limit / lane_sqrt(ft2);
  const Lane2 lag = damp / t.stiffness;
  sx = sliding ? ratio * (sx + lag * vtx) - lag * vtx : sx;
  sy = sliding ? ratio * (sy + lag * vty) - lag * vty : sy;
  ftx = sliding ? ftx * ratio : ftx;
  fty = sliding ? fty * ratio : fty;
  PairLaneForces out;
  out.fx = fn * nx + ftx;
  out.fy = fn * ny + fty;
  const Lane2 cross = nx * fty - ny * ftx;  // (n x F_t)_z
  out.torque_i = ri * cross;
  out.torque_j = rj * cross;
  out.shear_x = sx;
  out.shear_y = sy;
  return out;
}
}  // namespace

void Dem2dWorld::compute_forces() {
  const ContactParameters& c = settings_.contact;
  const TangentialConstants tc{c.tangential_stiffness, c.tangential_damping, c.friction, settings_.time_step_s};
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
  // fx, fy, torque hold the weights (kick_and_drift reset them).
  // Pass 1, without branches: the pairs in contact, in list order; the others lose their
  // tangential history (as LAMMPS).
  Pair* __restrict pairs = pairs_.data();
  std::uint32_t* __restrict touching = touching_.data();
  const std::size_t pair_total = pairs_.size();
  std::size_t touching_count = 0;
  for (std::size_t k = 0; k < pair_total; ++k) {
    Pair& p = pairs[k];
    const double dx = x[p.i] - x[p.j];
    const double dy = y[p.i] - y[p.j];
    const double radsum = r[p.i] + r[p.j];
    const bool in_contact = dx * dx + dy * dy < radsum * radsum;
    touching[touching_count] = static_cast<std::uint32_t>(k);
    touching_count += in_contact ? 1 : 0;
    p.shear_x = in_contact ? p.shear_x : 0.0;
    p.shear_y = in_contact ? p.shear_y : 0.0;
  }
  // Pass 2: the contact forces of two pairs at a time (one per SIMD lane; each lane does the
  // scalar arithmetic, so the result does not depend on the lane width), then added to both
  // discs of the first pair, then of the second: the same order as one pair at a time.
  const PairLaneConstants lc{kn, gn, tc};
  for (std::size_t t = 0; t < touching_count; t += 2) {
    const bool second = t + 1 < touching_count;
    Pair& p0 = pairs[touching[t]];
    Pair& p1 = pairs[touching[second ? t + 1 : t]];
    const PairLaneForces f = pair_lane_forces(p0, p1, x, y, vx, vy, w, r, lc);
    p0.shear_x = f.shear_x[0];
    p0.shear_y = f.shear_y[0];
    fx[p0.i] += f.fx[0];
    fy[p0.i] += f.fy[0];
    tq[p0.i] -= f.torque_i[0];
    fx[p0.j] -= f.fx[0];
    fy[p0.j] -= f.fy[0];
    tq[p0.j] -= f.torque_j[0];
    if (!second) break;
    p1.shear_x = f.shear_x[1];
    p1.shear_y = f.shear_y[1];
    fx[p1.i] += f.fx[1];
    fy[p1.i] += f.fy[1];
    tq[p1.i] -= f.torque_i[1];
    fx[p1.j] -= f.fx[1];
    fy[p1.j] -= f.fy[1];
    tq[p1.j] -= f.torque_j[1];
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
    const TangentialResult ft = tangential_force(wc.shear_x, wc.shear_y, vtx, vty, nx, ny, fn, meff, tc);
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

void Dem2dWorld::finish_half_kick() {
  if (!half_kick_pending_) return;
  const double h = half_step();
  for (std::size_t i = 0; i < count_; ++i) {
    vx_[i] += h * fx_[i] * inv_mass_[i];
    vy_[i] += h * fy_[i] * inv_mass_[i];
    omega_[i] += h * torque_[i] * inv_inertia_[i];
  }
  half_kick_pending_ = false;
}

void Dem2dWorld::kick_and_drift() {
  const double h = half_step();
  const double dt = settings_.time_step_s;
  const std::size_t n = count_;
  double* __restrict x = x_.data();
  double* __restrict y = y_.data();
  double* __restrict vx = vx_.data();
  double* __restrict vy = vy_.data();
  double* __restrict w = omega_.data();
  double* __restrict fx = fx_.data();
  double* __restrict fy = fy_.data();
  double* __restrict tq = torque_.data();
  const double* __restrict im = inv_mass_.data();
  const double* __restrict ii = inv_inertia_.data();
  const double* __restrict wx = weight_x_.data();
  const double* __restrict wy = weight_y_.data();
  // Two discs per SIMD lane pair (the per-lane arithmetic is the scalar one), the odd one last.
  const bool twice = half_kick_pending_;  // the last step's second half-kick, then this step's first
  const auto load = [](const double* p) {
    Lane2 v;
    std::memcpy(&v, p, sizeof v);
    return v;
  };
  const auto store = [](double* p, Lane2 v) { std::memcpy(p, &v, sizeof v); };
  Lane2 fastest = {0.0, 0.0};
  std::size_t i = 0;
  for (; i + 2 <= n; i += 2) {
    const Lane2 ax = h * load(fx + i) * load(im + i);
    const Lane2 ay = h * load(fy + i) * load(im + i);
    const Lane2 aw = h * load(tq + i) * load(ii + i);
    Lane2 u = load(vx + i) + ax;
    Lane2 v = load(vy + i) + ay;
    Lane2 o = load(w + i) + aw;
    if (twice) {
      u += ax;
      v += ay;
      o += aw;
    }
    store(vx + i, u);
    store(vy + i, v);
    store(w + i, o);
    store(x + i, load(x + i) + dt * u);
    store(y + i, load(y + i) + dt * v);
    const Lane2 speed_squared = u * u + v * v;
    fastest = speed_squared > fastest ? speed_squared : fastest;
    store(fx + i, load(wx + i));
    store(fy + i, load(wy + i));
    store(tq + i, Lane2{0.0, 0.0});
  }
  double fastest_squared = std::max(fastest[0], fastest[1]);
  for (; i < n; ++i) {
    const double ax = h * fx[i] * im[i];
    const double ay = h * fy[i] * im[i];
    const double aw = h * tq[i] * ii[i];
    double u = vx[i] + ax;
    double v = vy[i] + ay;
    double o = w[i] + aw;
    if (twice) {
      u += ax;
      v += ay;
      o += aw;
    }
    vx[i] = u;
    vy[i] = v;
    w[i] = o;
    x[i] += dt * u;
    y[i] += dt * v;
    fastest_squared = std::max(fastest_squared, u * u + v * v);
    fx[i] = wx[i];
    fy[i] = wy[i];
    tq[i] = 0.0;
  }
  half_kick_pending_ = false;
  travel_since_build_ += std::sqrt(fastest_squared) * dt;
}

void Dem2dWorld::step() {
  if (!lists_valid_) rebuild_lists();
  // Velocity Verlet: the forces of the previous step are in fx_, fy_, torque_.
  kick_and_drift();
  // Two discs approach each other by at most twice the longest travel: rebuild before the skin
  // could be crossed.
  if (2.0 * travel_since_build_ > settings_.skin) rebuild_lists();
  compute_forces();
  half_kick_pending_ = true;  // done by the next step's kick_and_drift (or finish_half_kick)
  ++steps_;
  time_ += settings_.time_step_s;
}

double Dem2dWorld::kinetic_energy() const {
  double e = 0;
  for (std::size_t i = 0; i < count_; ++i) {
    if (inv_mass_[i] == 0.0) continue;
    const double u = vx(i), v = vy(i), o = omega(i);
    e += 0.5 * mass_[i] * (u * u + v * v) + 0.5 * o * o / inv_inertia_[i];
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
