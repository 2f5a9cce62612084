#pragma once
// Writes the per-jiffy trace CSV of docs/programs.md (`--csv`) with a fixed number format, so the same seed gives
// the same bytes on every build.
#include <cstdio>
#include <string>

#include "dynweigh/hal/host/lockstep_session.hpp"

namespace dynweigh::tools {

class TraceCsv {
 public:
  explicit TraceCsv(const std::string& path);  // throws std::runtime_error if it cannot be created
  ~TraceCsv();
  TraceCsv(const TraceCsv&) = delete;
  TraceCsv& operator=(const TraceCsv&) = delete;

  void write(const hal::host::TraceRow& row);

 private:
  std::FILE* file_;
};

}  // namespace dynweigh::tools
