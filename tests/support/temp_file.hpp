#pragma once
// A path in /tmp for a test's file (an --nvm file, a recording): unique, absent at the start, removed
// at the end.
#include <unistd.h>

#include <cstdio>
#include <string>

namespace dynweigh::testing {

class TempFile {
 public:
  explicit TempFile(const char* stem = "dynweigh_test") {
    std::string name = std::string("/tmp/") + stem + "_XXXXXX";
    const int fd = ::mkstemp(name.data());
    if (fd >= 0) ::close(fd);
    path_ = name;
    std::remove(path_.c_str());
  }
  ~TempFile() { std::remove(path_.c_str()); }
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

}  // namespace dynweigh::testing
