#pragma once
// Solvers for the duct-flow Poisson problem. All stop on the same measure, the discrete L2 norm
// of the residual (see residual_norm), so their run times compare fairly; Gauss-Seidel can
// instead use the thesis' rule of example 3.1, the sum of the absolute changes of one sweep.
#include <string>
#include <vector>

#include "dynweigh/granular/poisson_problem.hpp"

namespace dynweigh::granular {

enum class PoissonSolverKind { gauss_seidel, sor, conjugate_gradient, direct, multigrid };

struct PoissonSolveOptions {
  double tolerance = 1e-10;  // on residual_norm (or on the change sum with the thesis rule)
  int max_iterations = 1000000;
  bool thesis_change_rule = false;  // Gauss-Seidel only: stop when sum |u_new - u_old| < tolerance
  double omega = 0.0;               // SOR only; 0 picks the optimum 2 / (1 + sin(pi h / side))
  int residual_check_interval = 10;  // sweeps between residual checks (Gauss-Seidel, SOR)
};

struct PoissonSolveReport {
  int iterations = 0;  // sweeps, CG iterations, V-cycles; 1 for the direct solver
  double residual = 0;
  bool converged = false;
};

// u holds the start value and the wall values on entry, the solution on return.
PoissonSolveReport solve_gauss_seidel(const PoissonProblem& p, std::vector<double>& u, const PoissonSolveOptions& o);
PoissonSolveReport solve_sor(const PoissonProblem& p, std::vector<double>& u, const PoissonSolveOptions& o);
PoissonSolveReport solve_conjugate_gradient(const PoissonProblem& p, std::vector<double>& u, const PoissonSolveOptions& o);
PoissonSolveReport solve_direct(const PoissonProblem& p, std::vector<double>& u, const PoissonSolveOptions& o);
// Geometric multigrid (V(2,2), red-black Gauss-Seidel, full weighting); n must be 2^k + 1.
PoissonSolveReport solve_multigrid(const PoissonProblem& p, std::vector<double>& u, const PoissonSolveOptions& o);

PoissonSolveReport solve_poisson(PoissonSolverKind kind, const PoissonProblem& p, std::vector<double>& u,
                                 const PoissonSolveOptions& o);
double optimal_sor_omega(const PoissonProblem& p);
bool parse_poisson_solver(const std::string& name, PoissonSolverKind& kind);
const char* poisson_solver_name(PoissonSolverKind kind);

}  // namespace dynweigh::granular
