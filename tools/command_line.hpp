#pragma once
// Every command's convention for its command line: help or version on stdout with exit 0, any
// other problem as one line on stderr ("<program>: <what>") with exit 2.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <optional>
#include <string>

namespace dynweigh::tools {

// Parses argv into `app`. Returns the exit status when the command ends here; nothing to go on.
inline std::optional<int> parse_command_line(CLI::App& app, int argc, char** argv, const char* program) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {  // --help, --version
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::string what = e.what();
    for (char& c : what) {
      if (c == '\n') c = ' ';
    }
    std::fprintf(stderr, "%s: %s\n", program, what.c_str());
    return 2;
  }
  return std::nullopt;
}

// A command's run-time failure, in one line: exit 1.
inline int fail(const char* command, const std::string& message) {
  std::fprintf(stderr, "dynweigh %s: %s\n", command, message.c_str());
  return 1;
}

}  // namespace dynweigh::tools
