#pragma once
namespace dynweigh::tools {

// Google Benchmark of Indicator::step while dosing (model strategy, float): `dynweigh bench --step`.
int run_step_benchmark(int argc, char** argv);

}  // namespace dynweigh::tools
