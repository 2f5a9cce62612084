// The Cortex-M4F image: the same firmware library as the host, on a board with a console UART and a
// plant link carrying the CAN frames of docs/can-protocol.md as SLCAN lines. One jiffy per 0x190 sample (the
// load-cell module paces the loop, lockstep or real time alike); SysTick counts 10 ms for the
// heartbeat and, once the board's `kLinkSilenceTicks` pass without a sample, for jiffies without
// one. Samples are put in order by their counter (hal/can/sample_sequence.hpp), as on Linux: a
// duplicate runs no jiffy, a late one is discarded, a lost one is a jiffy without a sample.
//
// Per-jiffy instruction budget: Indicator::step runs between dw_step_begin() and one of
// dw_step_end_idle() / dw_step_end_active(); a QEMU plugin (tests/targets/qemu_insn_plugin.cpp)
// counts the instructions between them.
#include <cstdint>

#include "dynweigh/firmware/indicator.hpp"
#include "dynweigh/firmware/ram_nvm.hpp"
#include "dynweigh/hal/can/protocol.hpp"
#include "dynweigh/hal/can/sample_sequence.hpp"
#include "dynweigh/hal/can/slcan.hpp"
#include "dynweigh/hal/cortexm/board_mps2_an386.hpp"
#include "dynweigh/hal/cortexm/cmsdk_uart.hpp"

using Board = dynweigh::hal::cortexm::BoardMps2An386;

namespace fw = dynweigh::firmware;
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

void send_frame(const can::CanFrame& frame) {
  char line[can::kSlcanMaxLine];
  const std::size_t n = can::slcan_encode(frame, line, sizeof line);
  if (g_plant_tx.free_space() < n) return;  // the link is saturated: drop whole frames only
  for (std::size_t i = 0; i < n; ++i) g_plant_tx.push(line[i]);
}

struct JiffyState {
  std::uint32_t jiffy = 0;
  fw::ValvePosition valve_position = fw::ValvePosition::closed;
  fw::LoadCellInput last_sample{0, 0, 0, false, fw::LinkStatus::ok};
  bool plant_heard = false;        // a frame from the plant ever came: silence is watched from then
  bool heard_since_jiffy = false;  // one came since the last jiffy
  std::uint32_t last_sample_tick = 0;
  std::uint32_t last_stand_in_tick = 0;
};

// `answer`: send the 0x220/0x181 pair (not for a jiffy standing in for a lost sample).
void run_jiffy(JiffyState& state, const fw::LoadCellInput& sample, bool answer = true) {
  state.heard_since_jiffy = false;
  char rx[128];
  std::size_t rx_length = 0;
  while (rx_length < sizeof rx && g_console_rx.pop(rx[rx_length])) ++rx_length;
  fw::Inputs inputs;
  inputs.jiffy = state.jiffy;
  inputs.load_cell = sample;
  inputs.valve_position = state.valve_position;
  inputs.console_rx = rx;
  inputs.console_rx_length = rx_length;

  dw_step_begin();
  const fw::Outputs out = g_indicator.step(inputs);
  if (out.state == fw::IndicatorState::idle) {
    dw_step_end_idle();
  } else {
    dw_step_end_active();
  }

  if (answer) {
    send_frame(can::encode(can::ValveCommandMessage{static_cast<std::uint8_t>(out.valve), out.valve_delay_100us,
                                                    out.answered_counter}));
    send_frame(can::encode(can::IndicatorStatusMessage{out.weight_100mg, static_cast<std::uint8_t>(out.state),
                                                       static_cast<std::uint8_t>(out.valve), out.answered_counter}));
  }
  // The console drains at the UART's pace: take from the indicator only what the ring can hold,
  // each '\n' going out as CR LF (a terminal on a serial line needs the CR), so at most half of it.
  char tx[128];
  for (std::size_t n; g_console_tx.free_space() >= 2 &&
                      (n = g_indicator.drain_console(tx, g_console_tx.free_space() / 2 < sizeof tx
                                                             ? g_console_tx.free_space() / 2
                                                             : sizeof tx)) > 0;) {
    for (std::size_t i = 0; i < n; ++i) push_console(tx[i]);
  }
  ++state.jiffy;
}

fw::LoadCellInput without_sample(const JiffyState& state, fw::LinkStatus link) {
  fw::LoadCellInput stale = state.last_sample;
  stale.fresh = false;
  stale.link = link;
  return stale;
}

void on_sample(JiffyState& state, can::SampleSequence& sequence, const can::LoadCellSampleMessage& m) {
  const can::SampleSequence::Arrival arrival = sequence.arrive(m.counter);
  if (!arrival.accept) return;  // the same sample again, or one the indicator is already past
  for (std::uint16_t i = 0; i < arrival.missing; ++i) {
    run_jiffy(state, without_sample(state, fw::LinkStatus::ok), /*answer=*/false);
  }
  state.last_sample = fw::LoadCellInput{m.raw_counts, m.counter, m.status, true, fw::LinkStatus::ok};
  state.last_sample_tick = g_ticks;
  run_jiffy(state, state.last_sample);
}

// A jiffy per tick without a sample once the link has been quiet for kLinkSilenceTicks.
void watch_silence(JiffyState& state, can::SampleSequence& sequence) {
  const std::uint32_t now = g_ticks;
  if (!state.plant_heard || now - state.last_sample_tick < Board::kLinkSilenceTicks) return;
  if (now == state.last_stand_in_tick) return;
  state.last_stand_in_tick = now;
  run_jiffy(state, without_sample(state, state.heard_since_jiffy ? fw::LinkStatus::ok : fw::LinkStatus::silent));
  sequence.stood_in();
}

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

  const char* banner = "dynweigh " ;
  for (const char* p = banner; *p; ++p) g_console_tx.push(*p);
  for (const char* p = fw::kFirmwareVersion; *p; ++p) g_console_tx.push(*p);
  for (const char* p = " on "; *p; ++p) g_console_tx.push(*p);
  for (const char* p = Board::kName; *p; ++p) g_console_tx.push(*p);
  push_console('\n');
  send_frame(can::encode(can::HeartbeatMessage{can::kNodeIndicator, can::kNmtBootUp}));

  can::SlcanDecoder decoder;
  can::SampleSequence sequence;
  JiffyState state;
  std::uint32_t heartbeat_tick = 0;
  for (;;) {
    while (console.rx_ready() && g_console_rx.free_space() > 0) g_console_rx.push(console.read());
    while (plant.rx_ready()) {
      can::CanFrame frame;
      if (!decoder.push(plant.read(), frame)) continue;
      if (!state.plant_heard) state.last_sample_tick = g_ticks;  // silence is counted from here
      state.plant_heard = state.heard_since_jiffy = true;  // a point-to-point link: no echo of our own
      switch (can::classify(frame)) {
        case can::MessageKind::load_cell_sample: {
          can::LoadCellSampleMessage m;
          if (can::decode(frame, m)) on_sample(state, sequence, m);
          break;
        }
        case can::MessageKind::valve_feedback: {
          can::ValveFeedbackMessage m;
          if (can::decode(frame, m)) state.valve_position = static_cast<fw::ValvePosition>(m.position);
          break;
        }
        default:
          break;
      }
      plant.pump(g_plant_tx);
    }
    watch_silence(state, sequence);
    if (g_ticks - heartbeat_tick >= 10) {  // CiA 301 heartbeat every 100 ms
      heartbeat_tick = g_ticks;
      send_frame(can::encode(can::HeartbeatMessage{can::kNodeIndicator, can::kNmtOperational}));
    }
    plant.pump(g_plant_tx);
    console.pump(g_console_tx);
  }
}
