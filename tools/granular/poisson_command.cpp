// dynweigh poisson: duct flow profile by Poisson's equation (thesis section 3.3).
#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include "command_line.hpp"
#include "finite_range.hpp"
#include "dynweigh/granular/poisson_problem.hpp"
#include "dynweigh/granular/poisson_solvers.hpp"
#include "granular_commands.hpp"

namespace dynweigh::tools {

using namespace dynweigh::granular;

namespace {

// Everything after the command line: solve, print, write the CSV.
int solve_and_report(int grid, const std::string& shape, const std::string& solver, double tol, double source,
                     double side, int max_iterations, bool thesis_rule, const std::string& csv) {
  PoissonSolverKind kind;
  parse_poisson_solver(solver, kind);
  if (kind == PoissonSolverKind::multigrid && ((grid - 1) & (grid - 2)) != 0) {
    return fail("poisson", "--solver mg needs --grid 2^k+1 (33, 65, 129, ...)");
  }
  std::ofstream out;  // opened before the solve: an unwritable path fails before the work, not after
  if (!csv.empty()) {
    out.open(csv);
    if (!out) return fail("poisson", "cannot write " + csv);
  }
  const PoissonProblem problem = make_duct_problem(grid, shape == "circle" ? DuctShape::circle : DuctShape::square, source, side);
  std::vector<double> u(problem.point_count(), 0.0);
  PoissonSolveOptions options;
  options.tolerance = tol;
  options.max_iterations = max_iterations;
  options.thesis_change_rule = thesis_rule;
  const auto start = std::chrono::steady_clock::now();
  const PoissonSolveReport report = solve_poisson(kind, problem, u, options);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const FlowProfile profile = flow_profile(problem, u);
  std::printf("grid=%d\nshape=%s\nsolver=%s\numax=%.9g\numean=%.9g\nalpha=%.6f\niterations=%d\nresidual=%.3e\nconverged=%d\nseconds=%.6f\n",
              grid, shape.c_str(), solver.c_str(), profile.max, profile.mean, profile.alpha(), report.iterations,
              report.residual, report.converged ? 1 : 0, seconds);
  if (shape == "square" && source == -1.0 && side == 1.0) {
    std::printf("umax_error=%.3e\numean_error=%.3e\n", std::fabs(profile.max - unit_square_series_value(0.5, 0.5)),
                std::fabs(profile.mean - unit_square_series_mean()));
  }
  if (out.is_open()) {
    out << "i,j,x,y,u\n";
    for (int j = 0; j < grid; ++j) {
      for (int i = 0; i < grid; ++i) out << i << ',' << j << ',' << i * problem.h << ',' << j * problem.h << ',' << u[problem.index(i, j)] << '\n';
    }
  }
  if (!report.converged) return fail("poisson", "did not reach the tolerance within --max-iterations");
  return 0;
}

}  // namespace

int run_poisson_command(int argc, char** argv) {
  CLI::App app{"Poisson duct flow (thesis section 3.3): laplacian(u) = f, u = 0 on the wall; alpha = mean/max"};
  int grid = 65;
  std::string shape = "square";
  std::string solver = "mg";
  double tol = 1e-10;
  double source = -1.0;
  double side = 1.0;
  int max_iterations = 1000000;
  bool thesis_rule = false;
  std::string csv;
  app.add_option("--grid", grid, "grid points per side, wall included (mg: 2^k+1)")->check(CLI::Range(3, 8193));
  app.add_option("--shape", shape, "cross-section")->check(CLI::IsMember({"square", "circle"}));
  app.add_option("--solver", solver, "gs, sor, cg, direct or mg")->check(CLI::IsMember({"gs", "sor", "cg", "direct", "mg"}));
  app.add_option("--tol", tol, "tolerance on the residual norm (gs --thesis-rule: on the change sum)")->check(PositiveFinite());
  app.add_option("--source", source, "f, the constant right-hand side")->check(Finite());
  app.add_option("--side", side, "side of the square / diameter of the circle")->check(PositiveFinite());
  app.add_option("--max-iterations", max_iterations, "iteration limit")->check(CLI::PositiveNumber);
  app.add_flag("--thesis-rule", thesis_rule, "gs: stop on the sum of absolute changes (thesis example 3.1)");
  app.add_option("--csv", csv, "write the profile: i,j,x,y,u");
  if (const auto exit_status = tools::parse_command_line(app, argc, argv, "dynweigh poisson")) return *exit_status;
  try {
    return solve_and_report(grid, shape, solver, tol, source, side, max_iterations, thesis_rule, csv);
  } catch (const std::exception& e) {
    return fail("poisson", e.what());
  }
}

}  // namespace dynweigh::tools
