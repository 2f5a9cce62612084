#pragma once
// `dynweigh term`: a console client for a serial device or pty. Takes argv with its own name in
// argv[0].
namespace dynweigh::tools {

int run_term_command(int argc, char** argv);

}  // namespace dynweigh::tools
