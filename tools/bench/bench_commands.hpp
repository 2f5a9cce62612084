#pragma once
namespace dynweigh::tools {

// dynweigh bench: strategies x scenarios x targets x seeds, run time against error (argv[0] = "bench").
int run_bench_command(int argc, char** argv);

}  // namespace dynweigh::tools
