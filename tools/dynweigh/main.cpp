// dynweigh: the project's command-line tool (docs/programs.md). One subcommand per job.
#include <cstdio>
#include <cstring>

#include "commands.hpp"
#ifdef DYNWEIGH_HAS_SIM
#include "sim_commands.hpp"
#endif
#ifdef DYNWEIGH_HAS_BENCH
#include "bench_commands.hpp"
#endif
#ifdef DYNWEIGH_HAS_GRANULAR
#include "granular_commands.hpp"
#endif
#ifdef DYNWEIGH_HAS_PLANT
#include "plant_commands.hpp"
#endif
#ifdef DYNWEIGH_HAS_REPLAY
#include "replay_commands.hpp"
#endif
#ifdef DYNWEIGH_HAS_TERM
#include "term_commands.hpp"
#endif
#ifdef DYNWEIGH_HAS_VIEW
#include "view_commands.hpp"
#endif

namespace {

using namespace dynweigh::tools;  // subcommands live here or at global scope

struct Subcommand {
  const char* name;
  const char* summary;
  int (*run)(int, char**);
};

constexpr Subcommand kSubcommands[] = {
    {"plot", "draw a cycle, replay or bench CSV as PNG or SVG with gnuplot", run_plot_command},
#ifdef DYNWEIGH_HAS_SIM
    {"sim", "run a scene open-loop with a valve schedule, write the cycle CSV", run_sim_command},
#endif
#ifdef DYNWEIGH_HAS_BENCH
    {"bench", "strategies x scenes x targets: run time against error (--step: Indicator::step, --sim: plant)",
     run_bench_command},
#endif
#ifdef DYNWEIGH_HAS_GRANULAR
    {"soc", "SOC sandpile (BTW): statistics and the avalanche force", run_soc_command},
    {"poisson", "Poisson duct flow: velocity profile and alpha", run_poisson_command},
    {"dem", "2D discrete element model of the silo", run_dem_command},
    {"calibrate", "a scene's lumped parameters from the DEM, SOC or Poisson models", run_calibrate_command},
#endif
#ifdef DYNWEIGH_HAS_PLANT
    {"plant", "the simulator as the load-cell and valve modules on a CAN transport", run_plant_command},
#endif
#ifdef DYNWEIGH_HAS_REPLAY
    {"replay", "recorded samples or inputs through the firmware's own step: what it decided", run_replay_command},
#endif
#ifdef DYNWEIGH_HAS_TERM
    {"term", "talk to a console on a serial device or pty; capture readtestdata as CSV", run_term_command},
#endif
#ifdef DYNWEIGH_HAS_VIEW
    {"view", "live window: silo, stream, pile and force trace while a scene runs", run_view_command},
#endif
};

void usage(std::FILE* out) {
  std::fprintf(out, "usage: dynweigh <subcommand> [options]   (dynweigh <subcommand> --help for its options)\n"
                    "       dynweigh --help | --version\n\n");
  for (const Subcommand& s : kSubcommands) std::fprintf(out, "  %-10s %s\n", s.name, s.summary);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    usage(stderr);
    return 2;
  }
  if (std::strcmp(argv[1], "--help") == 0 || std::strcmp(argv[1], "-h") == 0) {
    usage(stdout);
    return 0;
  }
  if (std::strcmp(argv[1], "--version") == 0) {
    std::printf("dynweigh %s\n", DYNWEIGH_VERSION);
    return 0;
  }
  for (const Subcommand& s : kSubcommands) {
    if (std::strcmp(argv[1], s.name) == 0) return s.run(argc - 1, argv + 1);
  }
  std::fprintf(stderr, "dynweigh: unknown subcommand '%s' (try dynweigh --help)\n", argv[1]);
  return 2;
}
