// dynweigh-bench-granular: run time against error of every Poisson solver, and the DEM's
// particle-steps per second on the LAMMPS peer's 2D silo (in.silo2d.*; tools/granular/compare_lammps.sh).
//
// Poisson: "error" is the largest difference to the converged discrete solution (a multigrid
// solve to a residual of 1e-10), so 1e-8 is reachable on every grid; the solvers stop on the
// residual norm at 5 * error (the smallest eigenvalue of -laplacian on the unit square is
// 2 pi^2 ~ 20 and the max norm of the slowest mode is twice its L2 norm, so that residual bounds
// the error by about error / 2), and the counter
// `error` reports what was actually reached. Gauss-Seidel is left out where it would take
// minutes (O(n^2) sweeps), the direct solver above 513^2 (fill-in).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "dynweigh/granular/poisson_problem.hpp"
#include "dynweigh/granular/poisson_solvers.hpp"
#include "dynweigh/granular/silo2d.hpp"

using namespace dynweigh::granular;

namespace {

const std::vector<double>& reference_solution(int n) {
  static std::map<int, std::vector<double>> cache;
  auto it = cache.find(n);
  if (it != cache.end()) return it->second;
  const PoissonProblem p = make_duct_problem(n, DuctShape::square);
  std::vector<double> u(p.point_count(), 0.0);
  PoissonSolveOptions o;
  o.tolerance = 1e-10;
  o.max_iterations = 200;
  solve_multigrid(p, u, o);
  return cache.emplace(n, std::move(u)).first->second;
}

void poisson_run(benchmark::State& state, PoissonSolverKind kind, int n, double target_error) {
  const PoissonProblem p = make_duct_problem(n, DuctShape::square);
  const std::vector<double>& reference = reference_solution(n);
  PoissonSolveOptions o;
  o.tolerance = 5.0 * target_error;
  PoissonSolveReport report;
  std::vector<double> u;
  for (auto _ : state) {
    u.assign(p.point_count(), 0.0);
    report = solve_poisson(kind, p, u, o);
    benchmark::DoNotOptimize(u.data());
  }
  double error = 0;
  for (std::size_t k = 0; k < u.size(); ++k) error = std::max(error, std::fabs(u[k] - reference[k]));
  state.counters["error"] = error;
  state.counters["iterations"] = report.iterations;
  state.counters["converged"] = report.converged ? 1 : 0;
}

void register_poisson() {
  const int grids[] = {33, 65, 129, 257, 513, 1025};
  const double errors[] = {1e-4, 1e-6, 1e-8};
  for (const auto kind : {PoissonSolverKind::gauss_seidel, PoissonSolverKind::sor, PoissonSolverKind::conjugate_gradient,
                          PoissonSolverKind::direct, PoissonSolverKind::multigrid}) {
    for (const int n : grids) {
      if (kind == PoissonSolverKind::gauss_seidel && n > 257) continue;
      if (kind == PoissonSolverKind::direct && n > 513) continue;
      for (const double e : errors) {
        if (kind == PoissonSolverKind::gauss_seidel && n == 257 && e < 1e-4) continue;
        const std::string name = std::string("Poisson/") + poisson_solver_name(kind) + "/" + std::to_string(n) +
                                 "/err:" + (e == 1e-4 ? "1e-4" : e == 1e-6 ? "1e-6" : "1e-8");
        benchmark::RegisterBenchmark(name.c_str(), [kind, n, e](benchmark::State& s) { poisson_run(s, kind, n, e); })
            ->Iterations(1)
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
      }
    }
  }
}

// The peer silo, settled once (120000 steps as in.silo2d.fill), shared by the DEM benchmarks.
const Dem2dWorld& settled_peer_silo() {
  static std::unique_ptr<Dem2dWorld> world;
  if (!world) {
    world = std::make_unique<Dem2dWorld>(make_silo2d(Silo2dConfig{}));
    world->run(120000);
  }
  return *world;
}

// particle_steps_per_s is per wall-clock second (the benchmarks use real time); on a shared
// machine particle_steps_per_cpu_s (process CPU time of the timed part) is the fairer figure.
double cpu_seconds_since(std::clock_t start) { return static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC; }

void BM_DemSilo2dFill(benchmark::State& state) {
  double particle_steps = 0, cpu = 0;
  for (auto _ : state) {
    Dem2dWorld world = make_silo2d(Silo2dConfig{});
    const std::clock_t start = std::clock();
    world.run(state.range(0));
    cpu += cpu_seconds_since(start);
    particle_steps += static_cast<double>(world.size()) * static_cast<double>(state.range(0));
  }
  state.counters["particle_steps_per_s"] = benchmark::Counter(particle_steps, benchmark::Counter::kIsRate);
  state.counters["particle_steps_per_cpu_s"] = cpu > 0 ? particle_steps / cpu : 0.0;
}
BENCHMARK(BM_DemSilo2dFill)->Arg(20000)->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_DemSilo2dDischarge(benchmark::State& state) {
  const Silo2dConfig config;
  double particle_steps = 0, cpu = 0;
  DischargeResult result;
  for (auto _ : state) {
    state.PauseTiming();
    Dem2dWorld world = settled_peer_silo();
    open_silo2d_orifice(world, config, static_cast<int>(state.range(0)));
    state.ResumeTiming();
    const std::clock_t start = std::clock();
    result = measure_silo2d_discharge(world, 2300, 600000, 2000);
    cpu += cpu_seconds_since(start);
    particle_steps += result.particle_steps;
  }
  state.counters["particle_steps_per_s"] = benchmark::Counter(particle_steps, benchmark::Counter::kIsRate);
  state.counters["particle_steps_per_cpu_s"] = cpu > 0 ? particle_steps / cpu : 0.0;
  state.counters["discharge_rate"] = result.rate;
  state.counters["steps"] = static_cast<double>(result.steps);
}
BENCHMARK(BM_DemSilo2dDischarge)->Arg(8)->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

int main(int argc, char** argv) {
  register_poisson();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
