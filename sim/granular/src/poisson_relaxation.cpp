// Gauss-Seidel (thesis example 3.1) and successive over-relaxation, lexicographic order.
#include <cmath>

#include "dynweigh/granular/poisson_solvers.hpp"

namespace dynweigh::granular {

namespace {
// One sweep of eq. 3.8 (dx = dy = h, so C = 4 / h^2), over-relaxed by omega; returns the sum of
// the absolute changes (the thesis' "change").
double relaxation_sweep(const PoissonProblem& p, std::vector<double>& u, double omega) {
  const auto n = static_cast<std::size_t>(p.n);
  const double h2 = p.h * p.h;
  double change = 0;
  for (std::size_t j = 1; j + 1 < n; ++j) {
    for (std::size_t i = 1; i + 1 < n; ++i) {
      const std::size_t k = j * n + i;
      if (!p.unknown[k]) continue;
      const double gauss_seidel = 0.25 * (u[k - 1] + u[k + 1] + u[k - n] + u[k + n] - h2 * p.source[k]);
      const double delta = omega * (gauss_seidel - u[k]);
      u[k] += delta;
      change += std::fabs(delta);
    }
  }
  return change;
}

PoissonSolveReport relax(const PoissonProblem& p, std::vector<double>& u, const PoissonSolveOptions& o,
                         double omega) {
  PoissonSolveReport report;
  const int check = o.residual_check_interval > 0 ? o.residual_check_interval : 1;
  for (int sweep = 1; sweep <= o.max_iterations; ++sweep) {
    const double change = relaxation_sweep(p, u, omega);
    report.iterations = sweep;
    if (o.thesis_change_rule) {
      if (change < o.tolerance) {
        report.converged = true;
        break;
      }
    } else if (sweep % check == 0 && residual_norm(p, u) < o.tolerance) {
      report.converged = true;
      break;
    }
  }
  report.residual = residual_norm(p, u);
  if (!o.thesis_change_rule && report.residual < o.tolerance) report.converged = true;
  return report;
}
}  // namespace

double optimal_sor_omega(const PoissonProblem& p) {
  // Young (1954): for the five-point Laplacian on a square of (n-1) intervals, the Jacobi
  // spectral radius is cos(pi / (n-1)), so omega = 2 / (1 + sin(pi / (n-1))). For the circle
  // the bounding square's value is close to optimal.
  const double pi = std::acos(-1.0);
  return 2.0 / (1.0 + std::sin(pi / (p.n - 1)));
}

PoissonSolveReport solve_gauss_seidel(const PoissonProblem& p, std::vector<double>& u, const PoissonSolveOptions& o) {
  return relax(p, u, o, 1.0);
}

PoissonSolveReport solve_sor(const PoissonProblem& p, std::vector<double>& u, const PoissonSolveOptions& o) {
  PoissonSolveOptions options = o;
  options.thesis_change_rule = false;
  return relax(p, u, options, o.omega > 0 ? o.omega : optimal_sor_omega(p));
}

}  // namespace dynweigh::granular
