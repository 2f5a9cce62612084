// dynweigh-granular: the three granular subcommands on their own, for scripts (compare_lammps.sh)
// and for trying them before the `dynweigh` tool dispatches to them.
#include <cstdio>
#include <cstring>

#include "granular_commands.hpp"

int main(int argc, char** argv) {
  if (argc < 2 || std::strcmp(argv[1], "--help") == 0) {
    std::puts("usage: dynweigh-granular soc|poisson|dem [options]   (each takes --help)");
    return argc < 2 ? 2 : 0;
  }
  const char* command = argv[1];
  if (std::strcmp(command, "soc") == 0) return dynweigh::tools::run_soc_command(argc - 1, argv + 1);
  if (std::strcmp(command, "poisson") == 0) return dynweigh::tools::run_poisson_command(argc - 1, argv + 1);
  if (std::strcmp(command, "dem") == 0) return dynweigh::tools::run_dem_command(argc - 1, argv + 1);
  if (std::strcmp(command, "calibrate") == 0) return dynweigh::tools::run_calibrate_command(argc - 1, argv + 1);
  std::fprintf(stderr, "dynweigh-granular: unknown command '%s'\n", command);
  return 2;
}
