#include "dynweigh/hal/host/file_settings_store.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>

namespace dynweigh::hal::host {

bool FileNvm::read(std::size_t offset, std::uint8_t* data, std::size_t length) const {
  if (offset + length > size()) return false;
  std::fill(data, data + length, std::uint8_t(0xFF));
  const int fd = ::open(path_.c_str(), O_RDONLY);
  if (fd < 0) return true;  // no file yet: erased memory
  const ssize_t n = ::pread(fd, data, length, off_t(offset));
  ::close(fd);
  return n >= 0;  // a short file reads as erased beyond its end
}

bool FileNvm::write(std::size_t offset, const std::uint8_t* data, std::size_t length) {
  if (offset + length > size()) return false;
  const int fd = ::open(path_.c_str(), O_WRONLY | O_CREAT, 0644);
  if (fd < 0) return false;
  const bool written = ::pwrite(fd, data, length, off_t(offset)) == ssize_t(length) && ::fsync(fd) == 0;
  ::close(fd);
  return written;
}

}  // namespace dynweigh::hal::host
