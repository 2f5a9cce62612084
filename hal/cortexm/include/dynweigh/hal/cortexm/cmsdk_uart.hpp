#pragma once
// ARM CMSDK APB UART (mps2 boards; QEMU's cmsdk-apb-uart): polled, with a transmit ring so the
// control loop never waits for the line. Reception is polled too: the loop spins between jiffies.
#include <cstddef>
#include <cstdint>

namespace dynweigh::hal::cortexm {

template <std::size_t N>
class ByteRing {
  static_assert(N > 0 && (N & (N - 1)) == 0, "ring capacity must be a power of two");

 public:
  std::size_t size() const { return head_ - tail_; }
  std::size_t free_space() const { return N - size(); }
  bool push(char c) {
    if (size() == N) return false;
    data_[head_++ & (N - 1)] = c;
    return true;
  }
  bool pop(char& c) {
    if (head_ == tail_) return false;
    c = data_[tail_++ & (N - 1)];
    return true;
  }

 private:
  char data_[N] = {};
  std::size_t head_ = 0, tail_ = 0;
};

class CmsdkUart {
 public:
  CmsdkUart(std::uintptr_t base, std::uint32_t clock_hz, std::uint32_t baud) : base_(base) {
    reg(kBaudDiv) = clock_hz / baud;
    reg(kCtrl) = kTxEnable | kRxEnable;
  }
  bool rx_ready() const { return (reg(kState) & kRxFull) != 0; }
  char read() const { return char(reg(kData) & 0xFFu); }
  bool tx_ready() const { return (reg(kState) & kTxFull) == 0; }
  void write(char c) const { reg(kData) = std::uint8_t(c); }

  template <std::size_t N>
  void pump(ByteRing<N>& tx) const {
    char c;
    while (tx_ready() && tx.pop(c)) write(c);
  }

 private:
  static constexpr std::uintptr_t kData = 0x00, kState = 0x04, kCtrl = 0x08, kBaudDiv = 0x10;
  static constexpr std::uint32_t kTxFull = 1u << 0, kRxFull = 1u << 1;
  static constexpr std::uint32_t kTxEnable = 1u << 0, kRxEnable = 1u << 1;
  volatile std::uint32_t& reg(std::uintptr_t offset) const {
    return *reinterpret_cast<volatile std::uint32_t*>(base_ + offset);
  }
  std::uintptr_t base_;
};

}  // namespace dynweigh::hal::cortexm
