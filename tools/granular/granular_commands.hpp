#pragma once
// Command lines of the granular detail models, called by the `dynweigh` tool's main:
//   dynweigh soc ...      SOC sandpiles (thesis section 3.2)
//   dynweigh poisson ...  Poisson duct flow (section 3.3)
//   dynweigh dem ...      2D DEM (section 3.4)
//   dynweigh calibrate .. a lumped scene from one of them
// argv[0] is the subcommand's name. Each prints key=value summary lines on stdout, writes a CSV
// with a header line with --csv FILE, and on bad input prints one line on stderr and returns
// non-zero (2 for usage errors, 1 for a run that fails).
namespace dynweigh::tools {

int run_soc_command(int argc, char** argv);
int run_poisson_command(int argc, char** argv);
int run_dem_command(int argc, char** argv);
int run_calibrate_command(int argc, char** argv);

}  // namespace dynweigh::tools
