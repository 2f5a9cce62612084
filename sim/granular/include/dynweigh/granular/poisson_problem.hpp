#pragma once
// Duct flow as Poisson's equation, thesis section 3.3: laplacian(u) = f on a cross-section with
// u = 0 on the wall (Dirichlet, eq. 3.7), discretised by the five-point stencil of eq. 3.6 on a
// uniform grid of n x n points (the outer ring is the wall of the square; for the circle every
// point outside the inscribed circle is held at zero, a staircase wall, first-order accurate).
#include <cstddef>
#include <cstdint>
#include <vector>

namespace dynweigh::granular {

enum class DuctShape { square, circle };

struct PoissonProblem {
  int n = 0;             // grid points per side, the wall included
  double side_m = 1.0;   // side of the square (diameter of the circle)
  double h = 0.0;        // grid spacing, side / (n - 1)
  DuctShape shape = DuctShape::square;
  std::vector<std::uint8_t> unknown;  // 1 where u is solved for, 0 where u is held (wall)
  std::vector<double> source;         // f at every point

  std::size_t index(int i, int j) const { return static_cast<std::size_t>(j) * static_cast<std::size_t>(n) + static_cast<std::size_t>(i); }
  std::size_t point_count() const { return static_cast<std::size_t>(n) * static_cast<std::size_t>(n); }
  std::size_t unknown_count() const;
  double cross_section_area() const;
};

// A uniform source f (the thesis' R_ij, constant); n >= 3.
PoissonProblem make_duct_problem(int n, DuctShape shape, double source = -1.0, double side_m = 1.0);

// Discrete L2 norm of the residual f - laplacian_h(u) over the unknowns: sqrt(h^2 sum r^2).
double residual_norm(const PoissonProblem& problem, const std::vector<double>& u);
// Same norm of the source, to scale a relative tolerance.
double source_norm(const PoissonProblem& problem);

// The flow profile's figures: peak, mean over the cross-section, and their ratio alpha, the
// thesis' correction to the mass flow (eq. 3.16). The mean is the trapezoidal rule (the wall is
// zero), second-order on the square.
struct FlowProfile {
  double max = 0;
  double mean = 0;
  double alpha() const { return max != 0 ? mean / max : 0.0; }
};
FlowProfile flow_profile(const PoissonProblem& problem, const std::vector<double>& u);

// Series solution for laplacian(u) = -1 on the unit square, u = 0 on the wall (separation of
// variables): u = x(1-x)/2 - (4/pi^3) sum_{k odd} sin(k pi x) cosh(k pi (y-1/2)) / (k^3 cosh(k pi/2)),
// mean = 1/12 - (16/pi^5) sum_{k odd} tanh(k pi/2) / k^5. docs/scenes.md: max 0.0736713, mean 0.0351442.
double unit_square_series_value(double x, double y);
double unit_square_series_mean();

}  // namespace dynweigh::granular
