#pragma once
// Output files of the tools (plots, CSVs) checked before the work that fills them, and gnuplot run
// so that a drawing it cannot write fails loudly instead of landing on stdout.
#include <string>

namespace dynweigh::tools {

// Opens `path` for appending (creating it, never truncating it) to learn before any work whether it
// can be written. Throws std::runtime_error "cannot write PATH: reason" (one line) if not. Returns
// true if the check created the file, so a caller that fails later can remove what it left.
bool check_writable(const std::string& path);

// Throws std::runtime_error (one line) unless `path` ends in `.extension` (case-insensitive).
void require_extension(const std::string& path, const std::string& extension, const std::string& what);

// Throws std::runtime_error (one line) if gnuplot cannot be started.
void require_gnuplot();

// Empties `output`, then runs gnuplot on `script`, which sets its output to `output`. gnuplot's stdout is discarded (it
// writes the picture there when it cannot open the output); throws std::runtime_error (one line:
// gnuplot's first complaint) if gnuplot fails or `output` is left empty.
void run_gnuplot(const std::string& script, const std::string& output);

}  // namespace dynweigh::tools
