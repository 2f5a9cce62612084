#pragma once
// --pty-link PATH: a stable name for the console's pty (as socat's link= makes), so a script can
// start dynweigh-fw in the background and open PATH without reading its stdout. Removed at exit.
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <string>
#include <sys/stat.h>

namespace dynweigh::tools {

class PtyLink {
 public:
  PtyLink() = default;
  // Replaces a symlink already at `path` (one a killed run left); refuses to replace anything else.
  PtyLink(const std::string& path, const std::string& device) : path_(path) {
    if (path.empty()) return;
    struct stat st {};
    if (::lstat(path.c_str(), &st) == 0) {
      if (!S_ISLNK(st.st_mode)) throw std::runtime_error("--pty-link " + path + ": exists and is not a symlink");
      ::unlink(path.c_str());
    }
    if (::symlink(device.c_str(), path.c_str()) != 0) {
      throw std::runtime_error("--pty-link " + path + ": " + std::strerror(errno));
    }
  }
  ~PtyLink() {
    if (!path_.empty()) ::unlink(path_.c_str());
  }
  PtyLink(const PtyLink&) = delete;
  PtyLink& operator=(const PtyLink&) = delete;

 private:
  std::string path_;
};

}  // namespace dynweigh::tools
