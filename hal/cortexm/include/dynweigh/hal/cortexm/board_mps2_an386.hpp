#pragma once
// The board type for QEMU's mps2-an386 (Cortex-M4F, 25 MHz): what differs from board to board is
// here and in the linker script, nothing else. To port (e.g. an STM32F407 with a CAN transceiver),
// write a board struct with the same members: the console UART, the plant link (SLCAN on a UART
// here; bxCAN on an STM32), the SysTick reload for 10 ms, and the factory settings.
#include <cstddef>
#include <cstdint>

#include "dynweigh/firmware/persistent_settings.hpp"

namespace dynweigh::hal::cortexm {

struct BoardMps2An386 {
  static constexpr const char* kName = "mps2-an386";
  static constexpr std::uint32_t kCpuHz = 25000000;
  static constexpr std::uint32_t kJiffyHz = 100;
  static constexpr std::uint32_t kSysTickReload = kCpuHz / kJiffyHz - 1;
  static_assert(kSysTickReload == 249999, "10 ms at 25 MHz");
  static_assert(kSysTickReload <= 0xFFFFFFu, "SysTick is a 24-bit counter");

  static constexpr std::uintptr_t kConsoleUart = 0x40004000;  // UART0: -serial #1
  static constexpr std::uintptr_t kPlantUart = 0x40005000;    // UART1: -serial #2, SLCAN
  static constexpr std::uint32_t kBaud = 115200;
  // The logbook's ring in RAM (one slot fewer kept): what the 32 KB leave beside the console rings.
  static constexpr std::size_t kRamLogbookSlots = 17;

  // Once the plant was heard, this many ticks without a sample run a jiffy without one (each tick
  // after that another), so a silent link becomes the can_silence fault 10 jiffies later. Generous
  // here: in QEMU the plant is a lockstep simulator on the host, and with -icount sleep=off its
  // pauses pass as virtual time several times faster than real time. A board with a real-time
  // load-cell module would use 3 (the Linux board's 25 ms).
  static constexpr std::uint32_t kLinkSilenceTicks = 300;
  static_assert(kCpuHz / kBaud >= 16, "CMSDK UART needs a baud divider of at least 16");

  // The factory calibration of the scale this board is sold with: here the default scene's
  // load cell (zero of the empty 4 kg container at 12000 counts, 1 count per gram), the plant
  // `dynweigh plant` simulates. No non-volatile storage on this board: `cal` lasts until reset.
  static firmware::PersistentSettings factory_settings() {
    firmware::PersistentSettings settings;
    settings.calibration.zero_counts = 12000;
    settings.calibration.counts_per_gram = 1.0f;
    settings.calibration.zero_set = true;
    settings.calibration.span_set = true;
    return settings;
  }
};

}  // namespace dynweigh::hal::cortexm
