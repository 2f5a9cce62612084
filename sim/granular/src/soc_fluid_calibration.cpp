#include "dynweigh/granular/soc_fluid_calibration.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "dynweigh/granular/extended_heap_2d.hpp"
#include "dynweigh/granular/poisson_problem.hpp"
#include "dynweigh/granular/poisson_solvers.hpp"
#include "dynweigh/granular/random.hpp"
#include "dynweigh/granular/soc_calibration.hpp"

namespace dynweigh::granular {

namespace {
// Least squares line y = a + b x.
void fit_line(const std::vector<double>& x, const std::vector<double>& y, double& a, double& b) {
  const double n = static_cast<double>(x.size());
  double mx = 0, my = 0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    mx += x[k];
    my += y[k];
  }
  mx /= n;
  my /= n;
  double sxy = 0, sxx = 0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    sxy += (x[k] - mx) * (y[k] - my);
    sxx += (x[k] - mx) * (x[k] - mx);
  }
  b = sxx > 0 ? sxy / sxx : 0;
  a = my - b * mx;
}
}  // namespace

SocSceneCalibration calibrate_from_soc(const sim::Scene& base, std::int64_t grains, std::int64_t large_size,
                                       int critical_step, std::uint64_t seed) {
  SocSceneCalibration c;
  c.scene = base;
  const double d = base.silo.grain_d_m;
  const int columns = std::max(8, static_cast<int>(std::lround(base.column.container_diameter_m / d)));
  c.columns = columns;
  c.grains = grains;
  c.cell_mass_kg = base.silo.bulk_density * d * d * base.column.container_diameter_m;
  ExtendedHeap2d heap(columns, critical_step, HeapEdges::closed_container);
  AvalancheForceModel model;
  model.grain_mass_kg = c.cell_mass_kg;
  model.step_height_m = d;
  model.gravity_m_s2 = base.g;
  SocCalibrator calibrator(model, large_size > 0 ? large_size : std::max<std::int64_t>(4, columns / 4));
  Random random(seed);
  // The height law while the heap is a free cone (before it reaches the walls): log h against
  // log N over the grains added until the base spans 80 % of the container.
  std::vector<double> log_n, log_h, n_values, h_squared;
  for (std::int64_t g = 1; g <= grains; ++g) {
    calibrator.record(heap.add_grain(heap.centre_column(), random));
    const auto& h = heap.heights();
    const bool free_cone = h[static_cast<std::size_t>(columns / 10)] == 0 && h[static_cast<std::size_t>(columns - 1 - columns / 10)] == 0;
    if (free_cone && g >= 16 && (g & (g - 1)) == 0) {  // powers of two: even in log N
      log_n.push_back(std::log(static_cast<double>(g)));
      log_h.push_back(std::log(static_cast<double>(heap.max_height())));
    }
    if (free_cone && g % 64 == 0) {
      n_values.push_back(static_cast<double>(g));
      h_squared.push_back(static_cast<double>(heap.max_height()) * heap.max_height());
    }
  }
  double a = 0;
  if (log_n.size() >= 2) fit_line(log_n, log_h, a, c.height_exponent);
  if (n_values.size() >= 2) {
    double slope_of_square = 0;
    fit_line(n_values, h_squared, a, slope_of_square);
    c.height_slope = slope_of_square;  // triangle of half-base h / s: N = h^2 / s
  }
  const SocLumpedParameters p = calibrator.result();
  c.critical_kg = p.critical_mass_kg;
  c.force_n = p.avalanche_force_n;
  c.duration_s = p.avalanche_duration_s;
  c.large_avalanches = p.large_avalanches;
  if (p.large_avalanches > 1 && c.critical_kg > 0 && c.duration_s > 0) {
    c.scene.avalanche.critical_kg = c.critical_kg;
    c.scene.avalanche.force_n = c.force_n;
    c.scene.avalanche.duration_s = c.duration_s;
  }
  if (c.height_slope > 0) {
    c.repose_angle_deg = std::atan(c.height_slope) * 180.0 / std::acos(-1.0);
    c.scene.column.repose_angle_deg = std::clamp(c.repose_angle_deg, 1.0, 89.0);
  }
  return c;
}

FluidSceneCalibration calibrate_from_fluid(const sim::Scene& base, int grid) {
  FluidSceneCalibration c;
  c.scene = base;
  c.grid = grid;
  const PoissonProblem problem = make_duct_problem(grid, DuctShape::circle, -1.0, base.silo.bore_m);
  std::vector<double> u(problem.point_count(), 0.0);
  PoissonSolveOptions options;
  options.tolerance = 1e-10;
  const PoissonSolveReport report = solve_poisson(PoissonSolverKind::multigrid, problem, u, options);
  c.iterations = report.iterations;
  c.alpha = flow_profile(problem, u).alpha();
  c.scene.silo.flow_factor = c.alpha;
  return c;
}

}  // namespace dynweigh::granular
