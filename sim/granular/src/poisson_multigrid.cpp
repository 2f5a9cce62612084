// Geometric multigrid for the five-point Poisson problem: V(2,2) cycles with red-black
// Gauss-Seidel smoothing, full-weighting restriction and bilinear prolongation (Briggs, Henson &
// McCormick, "A Multigrid Tutorial", 2nd ed., ch. 3). The circle's staircase wall is carried to
// the coarse grids by injection of the "unknown" flags.
#include <cmath>
#include <stdexcept>

#include "dynweigh/granular/poisson_solvers.hpp"

namespace dynweigh::granular {

namespace {
constexpr int kPreSmoothing = 2;
constexpr int kPostSmoothing = 2;
constexpr int kCoarsestSweeps = 50;

struct Level {
  int n = 0;
  double h = 0;
  std::vector<std::uint8_t> unknown;
  std::vector<double> u, f, r;
};

void smooth_red_black(Level& level, int sweeps) {
  const auto n = static_cast<std::size_t>(level.n);
  const double h2 = level.h * level.h;
  for (int s = 0; s < sweeps; ++s) {
    for (std::size_t colour = 0; colour < 2; ++colour) {
      for (std::size_t j = 1; j + 1 < n; ++j) {
        for (std::size_t i = 1 + ((j + colour) & 1); i + 1 < n; i += 2) {
          const std::size_t k = j * n + i;
          if (!level.unknown[k]) continue;
          level.u[k] = 0.25 * (level.u[k - 1] + level.u[k + 1] + level.u[k - n] + level.u[k + n] - h2 * level.f[k]);
        }
      }
    }
  }
}

void compute_residual(Level& level) {
  const auto n = static_cast<std::size_t>(level.n);
  const double inv_h2 = 1.0 / (level.h * level.h);
  for (std::size_t j = 1; j + 1 < n; ++j) {
    for (std::size_t i = 1; i + 1 < n; ++i) {
      const std::size_t k = j * n + i;
      level.r[k] = level.unknown[k]
                       ? level.f[k] - (level.u[k - 1] + level.u[k + 1] + level.u[k - n] + level.u[k + n] - 4.0 * level.u[k]) * inv_h2
                       : 0.0;
    }
  }
}

void restrict_residual(const Level& fine, Level& coarse) {
  const auto nf = static_cast<std::size_t>(fine.n);
  const auto nc = static_cast<std::size_t>(coarse.n);
  for (std::size_t J = 1; J + 1 < nc; ++J) {
    for (std::size_t I = 1; I + 1 < nc; ++I) {
      const std::size_t kc = J * nc + I;
      coarse.u[kc] = 0.0;
      if (!coarse.unknown[kc]) {
        coarse.f[kc] = 0.0;
        continue;
      }
      const std::size_t k = 2 * J * nf + 2 * I;
      const auto& r = fine.r;
      coarse.f[kc] = (4.0 * r[k] + 2.0 * (r[k - 1] + r[k + 1] + r[k - nf] + r[k + nf]) +
                      r[k - nf - 1] + r[k - nf + 1] + r[k + nf - 1] + r[k + nf + 1]) / 16.0;
    }
  }
}

void prolong_and_correct(const Level& coarse, Level& fine) {
  const auto nf = static_cast<std::size_t>(fine.n);
  const auto nc = static_cast<std::size_t>(coarse.n);
  const auto& e = coarse.u;
  for (std::size_t j = 1; j + 1 < nf; ++j) {
    for (std::size_t i = 1; i + 1 < nf; ++i) {
      const std::size_t k = j * nf + i;
      if (!fine.unknown[k]) continue;
      const std::size_t I = i / 2, J = j / 2;
      const std::size_t kc = J * nc + I;
      double correction;
      if (i % 2 == 0 && j % 2 == 0) {
        correction = e[kc];
      } else if (j % 2 == 0) {
        correction = 0.5 * (e[kc] + e[kc + 1]);
      } else if (i % 2 == 0) {
        correction = 0.5 * (e[kc] + e[kc + nc]);
      } else {
        correction = 0.25 * (e[kc] + e[kc + 1] + e[kc + nc] + e[kc + nc + 1]);
      }
      fine.u[k] += correction;
    }
  }
}

void v_cycle(std::vector<Level>& levels, std::size_t l) {
  Level& level = levels[l];
  if (l + 1 == levels.size()) {
    smooth_red_black(level, kCoarsestSweeps);
    return;
  }
  smooth_red_black(level, kPreSmoothing);
  compute_residual(level);
  restrict_residual(level, levels[l + 1]);
  v_cycle(levels, l + 1);
  prolong_and_correct(levels[l + 1], level);
  smooth_red_black(level, kPostSmoothing);
}

bool is_power_of_two_plus_one(int n) {
  const int m = n - 1;
  return m >= 2 && (m & (m - 1)) == 0;
}
}  // namespace

PoissonSolveReport solve_multigrid(const PoissonProblem& p, std::vector<double>& u, const PoissonSolveOptions& o) {
  if (!is_power_of_two_plus_one(p.n)) throw std::invalid_argument("multigrid needs n = 2^k + 1 grid points per side");
  std::vector<Level> levels;
  {
    Level finest;
    finest.n = p.n;
    finest.h = p.h;
    finest.unknown = p.unknown;
    finest.u = u;
    finest.f = p.source;
    finest.r.assign(p.point_count(), 0.0);
    levels.push_back(std::move(finest));
  }
  while (levels.back().n > 3) {
    const Level& fine = levels.back();
    Level coarse;
    coarse.n = (fine.n - 1) / 2 + 1;
    coarse.h = fine.h * 2;
    const auto nc = static_cast<std::size_t>(coarse.n);
    const auto nf = static_cast<std::size_t>(fine.n);
    coarse.unknown.assign(nc * nc, 0);
    for (std::size_t J = 1; J + 1 < nc; ++J) {
      for (std::size_t I = 1; I + 1 < nc; ++I) coarse.unknown[J * nc + I] = fine.unknown[2 * J * nf + 2 * I];
    }
    coarse.u.assign(nc * nc, 0.0);
    coarse.f.assign(nc * nc, 0.0);
    coarse.r.assign(nc * nc, 0.0);
    levels.push_back(std::move(coarse));
  }
  PoissonSolveReport report;
  for (int cycle = 1; cycle <= o.max_iterations; ++cycle) {
    v_cycle(levels, 0);
    report.iterations = cycle;
    if (residual_norm(p, levels[0].u) < o.tolerance) {
      report.converged = true;
      break;
    }
  }
  u = levels[0].u;
  report.residual = residual_norm(p, u);
  return report;
}

PoissonSolveReport solve_poisson(PoissonSolverKind kind, const PoissonProblem& p, std::vector<double>& u,
                                 const PoissonSolveOptions& o) {
  switch (kind) {
    case PoissonSolverKind::gauss_seidel: return solve_gauss_seidel(p, u, o);
    case PoissonSolverKind::sor: return solve_sor(p, u, o);
    case PoissonSolverKind::conjugate_gradient: return solve_conjugate_gradient(p, u, o);
    case PoissonSolverKind::direct: return solve_direct(p, u, o);
    case PoissonSolverKind::multigrid: return solve_multigrid(p, u, o);
  }
  return {};
}

bool parse_poisson_solver(const std::string& name, PoissonSolverKind& kind) {
  if (name == "gs") kind = PoissonSolverKind::gauss_seidel;
  else if (name == "sor") kind = PoissonSolverKind::sor;
  else if (name == "cg") kind = PoissonSolverKind::conjugate_gradient;
  else if (name == "direct") kind = PoissonSolverKind::direct;
  else if (name == "mg") kind = PoissonSolverKind::multigrid;
  else return false;
  return true;
}

const char* poisson_solver_name(PoissonSolverKind kind) {
  switch (kind) {
    case PoissonSolverKind::gauss_seidel: return "gs";
    case PoissonSolverKind::sor: return "sor";
    case PoissonSolverKind::conjugate_gradient: return "cg";
    case PoissonSolverKind::direct: return "direct";
    case PoissonSolverKind::multigrid: return "mg";
  }
  return "?";
}

}  // namespace dynweigh::granular
