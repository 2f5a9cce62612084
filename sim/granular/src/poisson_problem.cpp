#include "dynweigh/granular/poisson_problem.hpp"

#include <cmath>
#include <stdexcept>

namespace dynweigh::granular {

namespace {
const double kPi = std::acos(-1.0);
}

std::size_t PoissonProblem::unknown_count() const {
  std::size_t count = 0;
  for (const auto flag : unknown) count += flag;
  return count;
}

double PoissonProblem::cross_section_area() const {
  return shape == DuctShape::square ? side_m * side_m : kPi * side_m * side_m / 4.0;
}

PoissonProblem make_duct_problem(int n, DuctShape shape, double source, double side_m) {
  if (n < 3) throw std::invalid_argument("Poisson grid needs at least 3 points per side");
  if (!(side_m > 0)) throw std::invalid_argument("duct side must be positive");
  PoissonProblem p;
  p.n = n;
  p.side_m = side_m;
  p.h = side_m / (n - 1);
  p.shape = shape;
  p.unknown.assign(p.point_count(), 0);
  p.source.assign(p.point_count(), source);
  const double centre = side_m / 2.0;
  const double radius_squared = centre * centre;
  for (int j = 1; j < n - 1; ++j) {
    for (int i = 1; i < n - 1; ++i) {
      bool inside = true;
      if (shape == DuctShape::circle) {
        const double x = i * p.h - centre;
        const double y = j * p.h - centre;
        inside = x * x + y * y < radius_squared;
      }
      p.unknown[p.index(i, j)] = inside ? 1 : 0;
    }
  }
  return p;
}

double residual_norm(const PoissonProblem& p, const std::vector<double>& u) {
  const double inv_h2 = 1.0 / (p.h * p.h);
  const auto n = static_cast<std::size_t>(p.n);
  double sum = 0;
  for (std::size_t j = 1; j + 1 < n; ++j) {
    for (std::size_t i = 1; i + 1 < n; ++i) {
      const std::size_t k = j * n + i;
      if (!p.unknown[k]) continue;
      const double laplacian = (u[k - 1] + u[k + 1] + u[k - n] + u[k + n] - 4.0 * u[k]) * inv_h2;
      const double r = p.source[k] - laplacian;
      sum += r * r;
    }
  }
  return std::sqrt(sum * p.h * p.h);
}

double source_norm(const PoissonProblem& p) {
  double sum = 0;
  for (std::size_t k = 0; k < p.point_count(); ++k) {
    if (p.unknown[k]) sum += p.source[k] * p.source[k];
  }
  return std::sqrt(sum * p.h * p.h);
}

FlowProfile flow_profile(const PoissonProblem& p, const std::vector<double>& u) {
  FlowProfile profile;
  double sum = 0;
  double peak = 0;
  for (std::size_t k = 0; k < p.point_count(); ++k) {
    if (!p.unknown[k]) continue;
    sum += u[k];
    if (std::fabs(u[k]) > std::fabs(peak)) peak = u[k];
  }
  profile.max = peak;
  profile.mean = sum * p.h * p.h / p.cross_section_area();
  return profile;
}

double unit_square_series_value(double x, double y) {
  double sum = 0;
  for (int k = 1; k < 200; k += 2) {
    const double kp = k * kPi;
    // cosh ratio written with exponentials that cannot overflow
    const double a = kp * (y - 0.5);
    const double ratio = (std::exp(a - kp / 2) + std::exp(-a - kp / 2)) / (1.0 + std::exp(-kp));
    sum += std::sin(kp * x) * ratio / (static_cast<double>(k) * k * k);
  }
  return x * (1 - x) / 2 - 4.0 / (kPi * kPi * kPi) * sum;
}

double unit_square_series_mean() {
  double sum = 0;
  for (int k = 1; k < 200; k += 2) sum += std::tanh(k * kPi / 2) / std::pow(static_cast<double>(k), 5);
  return 1.0 / 12.0 - 16.0 / std::pow(kPi, 5) * sum;
}

}  // namespace dynweigh::granular
