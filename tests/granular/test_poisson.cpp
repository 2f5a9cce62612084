// Poisson duct flow against the series solution of the unit square (docs/scenes.md) and
// the exact Poiseuille profile of the circular duct; every solver reaches the same solution.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "dynweigh/granular/poisson_problem.hpp"
#include "dynweigh/granular/poisson_solvers.hpp"

using namespace dynweigh::granular;

namespace {
constexpr double kPublishedMax = 0.0736713;   // docs/scenes.md
constexpr double kPublishedMean = 0.0351442;  // docs/scenes.md

FlowProfile solve_square(int n, PoissonSolverKind kind, double tolerance) {
  const PoissonProblem p = make_duct_problem(n, DuctShape::square);
  std::vector<double> u(p.point_count(), 0.0);
  PoissonSolveOptions o;
  o.tolerance = tolerance;
  const PoissonSolveReport report = solve_poisson(kind, p, u, o);
  EXPECT_TRUE(report.converged) << poisson_solver_name(kind) << " n=" << n;
  return flow_profile(p, u);
}
}  // namespace

TEST(PoissonSeries, MatchesThePublishedFigures) {
  EXPECT_NEAR(unit_square_series_value(0.5, 0.5), kPublishedMax, 1e-7);
  EXPECT_NEAR(unit_square_series_mean(), kPublishedMean, 1e-7);
  EXPECT_NEAR(unit_square_series_value(0.0, 0.3), 0.0, 1e-12);
}

TEST(PoissonDuct, SquareConvergesAtSecondOrderOverFourGrids) {
  const int grids[] = {17, 33, 65, 129};
  double max_error[4], mean_error[4];
  for (int g = 0; g < 4; ++g) {
    const FlowProfile profile = solve_square(grids[g], PoissonSolverKind::multigrid, 1e-12);
    max_error[g] = std::fabs(profile.max - unit_square_series_value(0.5, 0.5));
    mean_error[g] = std::fabs(profile.mean - unit_square_series_mean());
  }
  for (int g = 0; g + 1 < 4; ++g) {
    const double max_order = std::log2(max_error[g] / max_error[g + 1]);
    const double mean_order = std::log2(mean_error[g] / mean_error[g + 1]);
    EXPECT_NEAR(max_order, 2.0, 0.1) << "grids " << grids[g] << " -> " << grids[g + 1];
    EXPECT_NEAR(mean_order, 2.0, 0.1) << "grids " << grids[g] << " -> " << grids[g + 1];
  }
  EXPECT_LT(max_error[3], 1e-3 * kPublishedMax);  // 0.1 % on the finest grid
}

TEST(PoissonDuct, AlphaOfTheSquareIsMeanOverMax) {
  const FlowProfile profile = solve_square(129, PoissonSolverKind::direct, 1e-9);
  EXPECT_NEAR(profile.max, kPublishedMax, 1e-3 * kPublishedMax);
  EXPECT_NEAR(profile.mean, kPublishedMean, 1e-3 * kPublishedMean);
  EXPECT_NEAR(profile.alpha(), kPublishedMean / kPublishedMax, 2e-3);
}

TEST(PoissonDuct, EverySolverReachesTheSameDiscreteSolution) {
  constexpr int kN = 33;
  const PoissonProblem p = make_duct_problem(kN, DuctShape::square);
  std::vector<double> reference(p.point_count(), 0.0);
  PoissonSolveOptions tight;
  tight.tolerance = 1e-11;
  ASSERT_TRUE(solve_direct(p, reference, tight).converged);
  for (const auto kind : {PoissonSolverKind::gauss_seidel, PoissonSolverKind::sor,
                          PoissonSolverKind::conjugate_gradient, PoissonSolverKind::multigrid}) {
    std::vector<double> u(p.point_count(), 0.0);
    const PoissonSolveReport report = solve_poisson(kind, p, u, tight);
    EXPECT_TRUE(report.converged) << poisson_solver_name(kind);
    double worst = 0;
    for (std::size_t k = 0; k < u.size(); ++k) worst = std::max(worst, std::fabs(u[k] - reference[k]));
    EXPECT_LT(worst, 1e-11) << poisson_solver_name(kind);
  }
}

TEST(PoissonDuct, SorWithOptimalOmegaNeedsFarFewerSweepsThanGaussSeidel) {
  const PoissonProblem p = make_duct_problem(65, DuctShape::square);
  PoissonSolveOptions o;
  o.tolerance = 1e-8;
  o.residual_check_interval = 1;
  std::vector<double> u_gs(p.point_count(), 0.0), u_sor(p.point_count(), 0.0);
  const auto gs = solve_gauss_seidel(p, u_gs, o);
  const auto sor = solve_sor(p, u_sor, o);
  ASSERT_TRUE(gs.converged);
  ASSERT_TRUE(sor.converged);
  // Spectral radii 1 - pi^2 h^2 against 1 - 2 pi h: the ratio of sweeps is about 2 / (pi h).
  EXPECT_GT(gs.iterations, 10 * sor.iterations);
}

TEST(PoissonDuct, ThesisExample31StopsAtAnAttainableTolerance) {
  // Table 3.1: 50 x 50 points, dx = dy = 0.2 (a 9.8 wide duct). The thesis' tolerance 1e-28 on
  // the change sum is below what double arithmetic resolves for u ~ 7; 1e-9 is reachable.
  const PoissonProblem p = make_duct_problem(50, DuctShape::square, -1.0, 49 * 0.2);
  PoissonSolveOptions o;
  o.thesis_change_rule = true;
  o.tolerance = 1e-9;
  std::vector<double> u(p.point_count(), 0.0);
  const auto report = solve_gauss_seidel(p, u, o);
  ASSERT_TRUE(report.converged);
  EXPECT_LT(report.iterations, 100000);
  // The square scales as side^2: u_max = 0.0736713 * 9.8^2 up to the O(h^2) grid error.
  const FlowProfile profile = flow_profile(p, u);
  EXPECT_NEAR(profile.max, kPublishedMax * 9.8 * 9.8, 2e-3 * kPublishedMax * 9.8 * 9.8);
}

TEST(PoissonDuct, CircleApproachesPoiseuille) {
  // laplacian(u) = -1 in a disc of radius R: u = (R^2 - r^2) / 4, so max R^2/4, mean R^2/8 and
  // alpha = 1/2 (laminar pipe flow). The staircase wall makes the error first order in h.
  const PoissonProblem p = make_duct_problem(257, DuctShape::circle);
  std::vector<double> u(p.point_count(), 0.0);
  PoissonSolveOptions o;
  o.tolerance = 1e-10;
  ASSERT_TRUE(solve_multigrid(p, u, o).converged);
  const FlowProfile profile = flow_profile(p, u);
  EXPECT_NEAR(profile.max, 0.0625, 0.01 * 0.0625);
  EXPECT_NEAR(profile.mean, 0.03125, 0.02 * 0.03125);
  EXPECT_NEAR(profile.alpha(), 0.5, 0.01);
}
