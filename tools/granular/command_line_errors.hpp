#pragma once
// Turns CLI11's parse outcome into the project's convention: help on stdout with exit 0, any
// other problem as one line on stderr with exit 2.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <string>

namespace dynweigh::tools {

inline int report_parse_outcome(const CLI::App& app, const CLI::ParseError& e, const char* command) {
  if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) {
    std::fputs(app.help().c_str(), stdout);
    return 0;
  }
  std::string what = e.what();
  for (char& c : what) {
    if (c == '\n') c = ' ';
  }
  std::fprintf(stderr, "dynweigh %s: %s\n", command, what.c_str());
  return 2;
}

inline int fail(const char* command, const std::string& message) {
  std::fprintf(stderr, "dynweigh %s: %s\n", command, message.c_str());
  return 1;
}

}  // namespace dynweigh::tools
