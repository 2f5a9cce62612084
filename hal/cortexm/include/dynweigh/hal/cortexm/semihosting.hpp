#pragma once
// ARM semihosting, used only to end a run in QEMU (-semihosting-config enable=on) with an exit
// status: SYS_EXIT_EXTENDED (0x20). On a real board without a debugger attached this would trap,
// so it is reached only from main's return and from fault handlers.
#include <cstdint>

namespace dynweigh::hal::cortexm {

[[noreturn]] inline void semihosting_exit(int status) {
  const std::uint32_t block[2] = {0x20026u /* ADP_Stopped_ApplicationExit */, std::uint32_t(status)};
  register std::uint32_t r0 asm("r0") = 0x20;  // SYS_EXIT_EXTENDED
  register const std::uint32_t* r1 asm("r1") = block;
  asm volatile("bkpt 0xAB" : : "r"(r0), "r"(r1) : "memory");
  for (;;) {
  }
}

}  // namespace dynweigh::hal::cortexm
