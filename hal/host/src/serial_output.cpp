#include "dynweigh/hal/host/serial_output.hpp"

#include <unistd.h>

namespace dynweigh::hal::host {

void SerialOutput::write(int fd, const char* data, std::size_t length) {
  for (std::size_t i = 0; i < length && size_ + 2 <= kCapacity; ++i) {
    if (data[i] == '\n') push('\r');
    push(data[i]);
  }
  flush(fd);
}

void SerialOutput::flush(int fd) {
  while (size_ > 0) {
    const std::size_t contiguous = head_ + size_ <= kCapacity ? size_ : kCapacity - head_;
    const ssize_t n = ::write(fd, ring_ + head_, contiguous);
    if (n <= 0) return;  // full (EAGAIN), interrupted, or nobody there: the rest goes next jiffy
    head_ = (head_ + std::size_t(n)) % kCapacity;
    size_ -= std::size_t(n);
  }
}

}  // namespace dynweigh::hal::host
