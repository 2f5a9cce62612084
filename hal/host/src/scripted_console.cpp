#include "dynweigh/hal/host/scripted_console.hpp"

#include <algorithm>

namespace dynweigh::hal::host {

std::size_t ScriptedConsole::read(char* destination, std::size_t capacity) {
  if (pending_.empty()) {
    if (busy_ || ended_) return 0;
    std::string line;
    switch (source_(line)) {
      case Poll::line: break;
      case Poll::nothing_yet: return 0;
      case Poll::ended: ended_ = true; return 0;
    }
    pending_ = line + "\n";
    busy_ = true;  // until the indicator says otherwise after this jiffy
  }
  const std::size_t n = std::min(capacity, pending_.size());
  std::copy_n(pending_.begin(), n, destination);
  pending_.erase(0, n);
  return n;
}

}  // namespace dynweigh::hal::host
