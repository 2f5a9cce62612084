#pragma once
// The `dynweigh` tool's subcommands; each takes argv with its own name in argv[0].
namespace dynweigh::tools {

int run_plot_command(int argc, char** argv);

}  // namespace dynweigh::tools
