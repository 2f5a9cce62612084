// The Cortex-M4F image: the same firmware library as the host, on a board with a console UART and a
// plant link carrying the CAN frames of docs/can-protocol.md as SLCAN lines. The indicator is the
// portable CAN node (hal/can/indicator_node.hpp), as on Linux: one jiffy per 0x190 sample (the
// load-cell module paces the loop, lockstep or real time alike), samples in order by their counter.
// This file is its adapter: the UARTs, and SysTick counting 10 ms for the heartbeat and, once the
// board's `kLinkSilenceTicks` pass without a sample, for jiffies without one.
//
// Per-jiffy instruction budget: Indicator::step runs between dw_step_begin() and one of
// dw_step_end_idle() / dw_step_end_active(), which run_one_jiffy calls through the node's StepProbe
// (StepMarks below); a QEMU plugin (tests/targets/qemu_insn_plugin.cpp)
// counts the instructions between them.
#include <cstdint>

#include "dynweigh/firmware/indicator.hpp"
#include "dynweigh/firmware/ram_nvm.hpp"
#include "dynweigh/hal/can/indicator_node.hpp"
#include "dynweigh/hal/can/protocol.hpp"
#include "dynweigh/hal/can/slcan.hpp"
#include "dynweigh/hal/cortexm/board_mps2_an386.hpp"
#include "dynweigh/hal/cortexm/cmsdk_uart.hpp"

using Board = dynweigh::hal::cortexm::BoardMps2An386;

namespace fw = dynweigh::firmware;
namespace hal = dynweigh::hal;
namespace can = dynweigh::hal::can;
using dynweigh::hal::cortexm::ByteRing;
using dynweigh::hal::cortexm::CmsdkUart;

extern "C" {
// Markers for the instruction-counting plugin; noipa keeps them out of line and unmerged.
__attribute__((noipa)) void dw_step_begin() { asm volatile("" ::: "memory"); }
__attribute__((noipa)) void dw_step_end_idle() { asm volatile("nop" ::: "memory"); }
__attribute__((noipa)) void dw_step_end_active() { asm volatile("nop\n nop" ::: "memory"); }
}

namespace {

volatile std::uint32_t g_ticks = 0;  // SysTick, 10 ms each

volatile std::uint32_t& reg(std::uintptr_t address) { return *reinterpret_cast<volatile std::uint32_t*>(address); }

void start_systick() {
  reg(0xE000E014) = Board::kSysTickReload;  // SYST_RVR
  reg(0xE000E018) = 0;                      // SYST_CVR
  reg(0xE000E010) = 0x7;                    // SYST_CSR: processor clock, interrupt, enable
}

fw::Indicator g_indicator(Board::factory_settings());
ByteRing<2048> g_console_tx;
ByteRing<256> g_console_rx;
ByteRing<512> g_plant_tx;

// Answers on the UART end in CR LF.
void push_console(char c) {
  if (c == '\n') g_console_tx.push('\r');
  g_console_tx.push(c);
}

// The console UART's rings as the indicator's console port.
class UartConsole final : public hal::ConsolePort {
 public:
  std::size_t read(char* destination, std::size_t capacity) override {
    std::size_t n = 0;
    while (n < capacity && g_console_rx.pop(destination[n])) ++n;
    return n;
  }
  void write(const char* data, std::size_t length) override {
    for (std::size_t i = 0; i < length; ++i) push_console(data[i]);
  }
  // The console drains at the UART's pace: only what the ring can hold, each '\n' going out as
  // CR LF (a terminal on a serial line needs the CR), so at most half of it, 128 bytes at a time.
  std::size_t writable() const override {
    const std::size_t room = g_console_tx.free_space() / 2;
    return room < 128 ? room : 128;
  }
};

// The plant UART's ring as the node's link: each frame one SLCAN line.
class SlcanLink final : public can::CanLink {
 public:
  void send(const can::CanFrame& frame) override {
    char line[can::kSlcanMaxLine];
    const std::size_t n = can::slcan_encode(frame, line, sizeof line);
    if (g_plant_tx.free_space() < n) return;  // the link is saturated: drop whole frames only
    for (std::size_t i = 0; i < n; ++i) g_plant_tx.push(line[i]);
  }
};

// Indicator::step between the markers the instruction-counting plugin looks for.
class StepMarks final : public hal::StepProbe {
 public:
  void before_step() override { dw_step_begin(); }
  void after_step(const fw::Outputs& out) override {
    if (out.state == fw::IndicatorState::idle) {
      dw_step_end_idle();
    } else {
      dw_step_end_active();
    }
  }
};

// The clock's side of link silence: once the plant has been heard, a jiffy per tick without a
// sample after kLinkSilenceTicks without one.
struct SilenceWatch {
  can::IndicatorNode& node;
  std::uint32_t last_sample_tick = 0;
  std::uint32_t last_stand_in_tick = 0;

  void heard(can::IndicatorNode::Heard what, bool first_frame) {
    if (first_frame || what == can::IndicatorNode::Heard::sample) last_sample_tick = g_ticks;
  }
  void watch() {
    const std::uint32_t now = g_ticks;
    if (!node.plant_heard() || now - last_sample_tick < Board::kLinkSilenceTicks) return;
    if (now == last_stand_in_tick) return;
    last_stand_in_tick = now;
    node.run_without_sample();
  }
};

}  // namespace

extern "C" void SysTick_Handler() { g_ticks = g_ticks + 1; }

extern "C" int board_main() {
  const CmsdkUart console(Board::kConsoleUart, Board::kCpuHz, Board::kBaud);
  const CmsdkUart plant(Board::kPlantUart, Board::kCpuHz, Board::kBaud);
  start_systick();
  // No non-volatile memory on this board: the logbook keeps the last results since reset in RAM
  // (a board with an EEPROM gives Logbook an NvmBlock over it). Here, not a global: board_main
  // never returns, and no destructor is registered.
  fw::RamLogbook<Board::kRamLogbookSlots> logbook;
  g_indicator.attach_logbook(&logbook.logbook());
  UartConsole console_port;
  SlcanLink link;
  StepMarks step_marks;
  can::IndicatorNode node(g_indicator, console_port, link, can::IndicatorNodeOptions{nullptr, 0, &step_marks});

  const char* banner = "dynweigh " ;
  for (const char* p = banner; *p; ++p) g_console_tx.push(*p);
  for (const char* p = fw::kFirmwareVersion; *p; ++p) g_console_tx.push(*p);
  for (const char* p = " on "; *p; ++p) g_console_tx.push(*p);
  for (const char* p = Board::kName; *p; ++p) g_console_tx.push(*p);
  push_console('\n');
  node.send_heartbeat(can::kNmtBootUp);

  can::SlcanDecoder decoder;
  SilenceWatch silence{node};
  std::uint32_t heartbeat_tick = 0;
  for (;;) {
    while (console.rx_ready() && g_console_rx.free_space() > 0) g_console_rx.push(console.read());
    while (plant.rx_ready()) {
      can::CanFrame frame;
      if (!decoder.push(plant.read(), frame)) continue;
      const bool first_frame = !node.plant_heard();  // silence is counted from here
      silence.heard(node.receive(frame), first_frame && node.plant_heard());
      plant.pump(g_plant_tx);
    }
    silence.watch();
    if (g_ticks - heartbeat_tick >= 10) {  // CiA 301 heartbeat every 100 ms
      heartbeat_tick = g_ticks;
      node.send_heartbeat(can::kNmtOperational);
    }
    plant.pump(g_plant_tx);
    console.pump(g_console_tx);
  }
}
