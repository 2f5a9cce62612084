#pragma once
// A non-volatile memory that is not: RAM, erased (0xFF) at start-up. For a board without storage,
// so the logbook still holds the results since power-up.
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "dynweigh/firmware/logbook.hpp"

namespace dynweigh::firmware {

template <std::size_t Bytes>
class RamNvm final : public NvmBlock {
 public:
  RamNvm() { std::memset(bytes_, 0xFF, Bytes); }
  // Never allocated: the deleting destructor the vtable names must not pull the heap's free() into
  // a board image that has none.
  static void operator delete(void*) {}
  std::size_t size() const override { return Bytes; }
  bool read(std::size_t offset, std::uint8_t* data, std::size_t length) const override {
    if (offset > Bytes || length > Bytes - offset) return false;
    std::memcpy(data, bytes_ + offset, length);
    return true;
  }
  bool write(std::size_t offset, const std::uint8_t* data, std::size_t length) override {
    if (offset > Bytes || length > Bytes - offset) return false;
    std::memcpy(bytes_ + offset, data, length);
    return true;
  }

 private:
  std::uint8_t bytes_[Bytes];
};

// A logbook in RAM of `Slots` records (Slots - 1 kept), opened.
template <std::size_t Slots>
class RamLogbook {
 public:
  RamLogbook() { logbook_.open(); }
  RamLogbook(const RamLogbook&) = delete;
  RamLogbook& operator=(const RamLogbook&) = delete;
  Logbook& logbook() { return logbook_; }

 private:
  RamNvm<Slots * kLogRecordSize> nvm_;
  Logbook logbook_{nvm_, 0, Slots};
};

}  // namespace dynweigh::firmware
