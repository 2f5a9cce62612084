// Reset and exception vectors for a Cortex-M4F. The reset handler enables the FPU before any float
// code runs, copies .data, zeroes .bss, runs the static constructors, then board_main().
#include <cstdint>

#include "dynweigh/hal/cortexm/semihosting.hpp"

extern "C" {
extern std::uint32_t _sidata, _sdata, _edata, _sbss, _ebss, _estack;
extern void (*__preinit_array_start[])();
extern void (*__preinit_array_end[])();
extern void (*__init_array_start[])();
extern void (*__init_array_end[])();
int board_main();  // main.cpp; not `main`, which C++ forbids calling
void Reset_Handler();
void SysTick_Handler();
void Default_Handler();
void HardFault_Handler();
}

namespace {
volatile std::uint32_t& reg(std::uintptr_t address) { return *reinterpret_cast<volatile std::uint32_t*>(address); }
constexpr std::uintptr_t kCpacr = 0xE000ED88;
}  // namespace

extern "C" void Reset_Handler() {
  reg(kCpacr) = reg(kCpacr) | (0xFu << 20);  // CP10, CP11: full access
  asm volatile("dsb\n isb" ::: "memory");
  std::uint32_t* src = &_sidata;
  for (std::uint32_t* dst = &_sdata; dst < &_edata;) *dst++ = *src++;
  for (std::uint32_t* dst = &_sbss; dst < &_ebss;) *dst++ = 0;
  for (auto f = __preinit_array_start; f < __preinit_array_end; ++f) (*f)();
  for (auto f = __init_array_start; f < __init_array_end; ++f) (*f)();
  const int status = board_main();
  dynweigh::hal::cortexm::semihosting_exit(status);
}

extern "C" void Default_Handler() { dynweigh::hal::cortexm::semihosting_exit(120); }
extern "C" void HardFault_Handler() { dynweigh::hal::cortexm::semihosting_exit(121); }

using Vector = void (*)();
extern "C" __attribute__((section(".isr_vector"), used)) const Vector g_vectors[16 + 16] = {
    reinterpret_cast<Vector>(&_estack),
    Reset_Handler,
    Default_Handler,    // NMI
    HardFault_Handler,  // HardFault
    Default_Handler,    // MemManage
    Default_Handler,    // BusFault
    Default_Handler,    // UsageFault
    nullptr, nullptr, nullptr, nullptr,
    Default_Handler,  // SVCall
    Default_Handler,  // DebugMonitor
    nullptr,
    Default_Handler,  // PendSV
    SysTick_Handler,
    // External interrupts: none enabled (the UARTs are polled).
    Default_Handler, Default_Handler, Default_Handler, Default_Handler, Default_Handler, Default_Handler,
    Default_Handler, Default_Handler, Default_Handler, Default_Handler, Default_Handler, Default_Handler,
    Default_Handler, Default_Handler, Default_Handler, Default_Handler,
};

// The ports' virtual destructors put a deleting destructor in each vtable, which names operator
// delete; nothing here is ever allocated (operator new does not link), so none is ever called.
void operator delete(void*) noexcept { dynweigh::hal::cortexm::semihosting_exit(122); }
void operator delete(void*, std::size_t) noexcept { dynweigh::hal::cortexm::semihosting_exit(122); }
