#pragma once
// `dynweigh replay`: recorded samples or inputs through the firmware's own step function.
// Takes argv with its own name in argv[0].
namespace dynweigh::tools {

int run_replay_command(int argc, char** argv);

}  // namespace dynweigh::tools
