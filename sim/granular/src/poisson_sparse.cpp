// Conjugate gradient and sparse Cholesky (LDL^T) on the assembled matrix of -laplacian_h, via
// Eigen's sparse module. -laplacian_h is symmetric positive definite, as both need.
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include "dynweigh/granular/poisson_solvers.hpp"

namespace dynweigh::granular {

namespace {
struct AssembledSystem {
  Eigen::SparseMatrix<double> matrix;
  Eigen::VectorXd rhs;
  std::vector<int> unknown_of_point;  // -1 for held points
  std::vector<std::size_t> point_of_unknown;
};

AssembledSystem assemble(const PoissonProblem& p, const std::vector<double>& u) {
  AssembledSystem s;
  s.unknown_of_point.assign(p.point_count(), -1);
  for (std::size_t k = 0; k < p.point_count(); ++k) {
    if (p.unknown[k]) {
      s.unknown_of_point[k] = static_cast<int>(s.point_of_unknown.size());
      s.point_of_unknown.push_back(k);
    }
  }
  const auto count = static_cast<Eigen::Index>(s.point_of_unknown.size());
  const auto n = static_cast<std::size_t>(p.n);
  const double inv_h2 = 1.0 / (p.h * p.h);
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(static_cast<std::size_t>(count) * 5);
  s.rhs.resize(count);
  for (Eigen::Index row = 0; row < count; ++row) {
    const std::size_t k = s.point_of_unknown[static_cast<std::size_t>(row)];
    double b = -p.source[k];
    triplets.emplace_back(row, row, 4.0 * inv_h2);
    for (const std::size_t neighbour : {k - 1, k + 1, k - n, k + n}) {
      const int column = s.unknown_of_point[neighbour];
      if (column >= 0) {
        triplets.emplace_back(row, column, -inv_h2);
      } else {
        b += u[neighbour] * inv_h2;  // wall value moves to the right-hand side
      }
    }
    s.rhs[row] = b;
  }
  s.matrix.resize(count, count);
  s.matrix.setFromTriplets(triplets.begin(), triplets.end());
  return s;
}

void scatter(const AssembledSystem& s, const Eigen::VectorXd& x, std::vector<double>& u) {
  for (std::size_t row = 0; row < s.point_of_unknown.size(); ++row) {
    u[s.point_of_unknown[row]] = x[static_cast<Eigen::Index>(row)];
  }
}
}  // namespace

PoissonSolveReport solve_conjugate_gradient(const PoissonProblem& p, std::vector<double>& u, const PoissonSolveOptions& o) {
  const AssembledSystem s = assemble(p, u);
  Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper> cg;
  cg.setMaxIterations(o.max_iterations);
  // Eigen stops on |r| / |b| in the plain 2-norm; both carry the same h factor as residual_norm,
  // so the relative tolerance is the absolute one over the source norm.
  const double b_norm = source_norm(p);
  cg.setTolerance(b_norm > 0 ? o.tolerance / b_norm : o.tolerance);
  cg.compute(s.matrix);
  Eigen::VectorXd x0(s.rhs.size());
  for (std::size_t row = 0; row < s.point_of_unknown.size(); ++row) x0[static_cast<Eigen::Index>(row)] = u[s.point_of_unknown[row]];
  const Eigen::VectorXd x = cg.solveWithGuess(s.rhs, x0);
  scatter(s, x, u);
  PoissonSolveReport report;
  report.iterations = static_cast<int>(cg.iterations());
  report.residual = residual_norm(p, u);
  report.converged = report.residual < o.tolerance;
  return report;
}

PoissonSolveReport solve_direct(const PoissonProblem& p, std::vector<double>& u, const PoissonSolveOptions& o) {
  const AssembledSystem s = assemble(p, u);
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(s.matrix);  // AMD ordering
  PoissonSolveReport report;
  report.iterations = 1;
  if (ldlt.info() != Eigen::Success) return report;
  scatter(s, ldlt.solve(s.rhs), u);
  report.residual = residual_norm(p, u);
  report.converged = report.residual < o.tolerance;
  return report;
}

}  // namespace dynweigh::granular
