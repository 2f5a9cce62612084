#pragma once
// `dynweigh sim` (run a scene open-loop with a valve schedule, write the cycle CSV) and
// `dynweigh bench --sim` (per shipped scene: real-time factor and error against a 10x finer step).
// Each takes argv with its own name in argv[0].

int run_sim_command(int argc, char** argv);
int run_sim_bench(int argc, char** argv);
