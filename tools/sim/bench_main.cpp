// dynweigh-sim-bench: the plant benchmark on its own, until `dynweigh bench --sim` calls it.
#include "sim_commands.hpp"

int main(int argc, char** argv) { return run_sim_bench(argc, argv); }
