#pragma once
// `dynweigh view`: the live window. Takes argv with its own name in argv[0].
namespace dynweigh::tools {

int run_view_command(int argc, char** argv);

}  // namespace dynweigh::tools
