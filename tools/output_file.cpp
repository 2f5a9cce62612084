#include "output_file.hpp"

#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <stdexcept>

namespace dynweigh::tools {
namespace {

std::string first_line_of(const std::string& path) {
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    if (line.find_first_not_of(" \t\r^") != std::string::npos) return line;  // gnuplot points with ^ lines
  }
  return "";
}

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return text;
}

}  // namespace

bool check_writable(const std::string& path) {
  struct stat st {};
  const bool existed = ::stat(path.c_str(), &st) == 0;
  if (existed && S_ISDIR(st.st_mode)) throw std::runtime_error("cannot write " + path + ": it is a directory");
  std::FILE* f = std::fopen(path.c_str(), "ab");
  if (!f) throw std::runtime_error("cannot write " + path + ": " + std::strerror(errno));
  std::fclose(f);
  return !existed;
}

void require_extension(const std::string& path, const std::string& extension, const std::string& what) {
  const std::string suffix = "." + extension;
  if (path.size() <= suffix.size() || lower(path.substr(path.size() - suffix.size())) != suffix) {
    std::string format = extension;
    std::transform(format.begin(), format.end(), format.begin(), [](unsigned char c) { return char(std::toupper(c)); });
    throw std::runtime_error(what + " writes " + format + " only: " + path + " does not end in " + suffix);
  }
}

void require_gnuplot() {
  const int status = std::system("gnuplot --version >/dev/null 2>&1");
  if (status == -1 || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    throw std::runtime_error("gnuplot not found (apt-get install gnuplot-nox)");
  }
}

void run_gnuplot(const std::string& script, const std::string& output) {
  // Emptied first, so a picture that did not arrive shows as an empty file, not last run's.
  std::FILE* target = std::fopen(output.c_str(), "wb");
  if (!target) throw std::runtime_error("cannot write " + output + ": " + std::strerror(errno));
  std::fclose(target);
  char errors[] = "/tmp/dynweigh-gnuplot-XXXXXX";
  const int fd = ::mkstemp(errors);
  if (fd < 0) throw std::runtime_error(std::string("cannot create a temporary file: ") + std::strerror(errno));
  ::close(fd);
  const std::string command = std::string("gnuplot >/dev/null 2>'") + errors + "'";
  std::FILE* gnuplot = ::popen(command.c_str(), "w");
  if (!gnuplot) {
    std::remove(errors);
    throw std::runtime_error("cannot start gnuplot (apt-get install gnuplot-nox)");
  }
  std::fwrite(script.data(), 1, script.size(), gnuplot);
  const int status = ::pclose(gnuplot);
  const std::string complaint = first_line_of(errors);
  std::remove(errors);
  struct stat st {};
  const bool drawn = ::stat(output.c_str(), &st) == 0 && st.st_size > 0;
  if (status != 0 || !drawn) {
    throw std::runtime_error("gnuplot did not draw " + output + (complaint.empty() ? "" : ": " + complaint));
  }
}

}  // namespace dynweigh::tools
