#pragma once
// The indicator on the Linux CAN board (hal/linux/can_board.hpp) against the simulated plant
// playing the load-cell and valve modules (docs/can-protocol.md), over the in-process `udp:` loopback transport,
// with the fault-injecting wrapper (hal/linux/faulty_can_transport.hpp) on the indicator's side.
// One thread, lockstep: per plant jiffy k the plant sends its valve feedback and sample k, the board
// runs what arrived, and the plant takes the 0x220 carrying k. An answer that does not come is what
// a real-time valve module would live through: the plant waits one jiffy of wall time for it (the
// board keeps running meanwhile, so its timers fire), keeps the last command, and closes after
// 50 ms without one (the valve module's watchdog, docs/can-protocol.md). The plant's truth is the measure, never the indicator.
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>

#include "dynweigh/firmware/indicator.hpp"
#include "dynweigh/hal/can/protocol.hpp"
#include "dynweigh/hal/host/simulated_plant_ports.hpp"
#include "dynweigh/hal/linux/can_board.hpp"
#include "dynweigh/hal/linux/can_transport.hpp"
#include "dynweigh/hal/linux/faulty_can_transport.hpp"
#include "dynweigh/sim/plant.hpp"
#include "dynweigh/sim/scene.hpp"
#include "support/string_console.hpp"

namespace dynweigh::testing {

class CanFaultRig {
 public:
  static constexpr double kJiffyS = 0.010;
  static constexpr int kAnswerWaitMs = 10;            // one jiffy: then the exchange is lost
  static constexpr std::uint32_t kWatchdogJiffies = 5;  // docs/can-protocol.md: no command for 50 ms -> close

  explicit CanFaultRig(hal::linux_can::CanFaultPlan plan, const sim::Scene& scene = sim::default_scene(),
                       std::uint64_t seed = 1)
      : plant_(scene, seed), indicator_(hal::host::factory_settings(plant_)) {
    open_links();
    faulty_ = std::make_unique<hal::linux_can::FaultyCanTransport>(*board_link_, std::move(plan));
    board_ = std::make_unique<hal::linux_can::CanBoard>(*faulty_, indicator_, console_);
  }

  // Sends one command line and runs until its answer ends (OK or ERR) or `max_jiffies` pass. Unlike
  // FaultRig it does not wait for the test-data record to end: on a dead link every jiffy costs
  // 10 ms of wall time.
  std::string run_command(const std::string& line, std::uint32_t max_jiffies = 200) {
    console_.pending = line + "\n";
    console_.output.clear();
    for (std::uint32_t i = 0; i < max_jiffies; ++i) {
      step();
      if (console_.pending.empty() && ends_with_answer(console_.output)) break;
    }
    return console_.output;
  }

  void idle(std::uint32_t jiffies) {
    for (std::uint32_t i = 0; i < jiffies; ++i) step();
  }

  // One plant jiffy.
  void step() {
    namespace can = hal::can;
    const std::uint32_t k = plant_jiffy_;
    if (k % 10 == 0) {  // every 100 ms of plant time, as dynweigh plant does
      plant_link_->send(can::encode(can::HeartbeatMessage{can::kNodeLoadCell, can::kNmtOperational}));
      plant_link_->send(can::encode(can::HeartbeatMessage{can::kNodeValve, can::kNmtOperational}));
    }
    const sim::LoadCellSample s = plant_.sample();
    plant_link_->send(can::encode(can::ValveFeedbackMessage{static_cast<std::uint8_t>(plant_.valve_feedback()), 0}));
    plant_link_->send(can::encode(can::LoadCellSampleMessage{s.raw_counts, s.counter, s.status}));
    can::ValveCommandMessage answer;
    if (await_answer(s.counter, answer)) {
      plant_.command_valve(static_cast<sim::ValveCommand>(answer.command), answer.delay_100us * 1e-4);
      last_answer_jiffy_ = k;
      watchdog_closed_ = false;
      ++answers_;
    } else if (k - last_answer_jiffy_ >= kWatchdogJiffies && !watchdog_closed_) {
      plant_.command_valve(sim::ValveCommand::closed, 0.0);
      watchdog_closed_ = true;
      ++watchdog_closes_;
    }
    const double released_before_kg = plant_.truth().released_kg;
    plant_.advance(kJiffyS);
    if (plant_.truth().released_kg - released_before_kg > max_release_per_jiffy_kg_) {
      max_release_per_jiffy_kg_ = plant_.truth().released_kg - released_before_kg;
    }
    ++plant_jiffy_;
  }

  sim::Plant& plant() { return plant_; }
  firmware::Indicator& indicator() { return indicator_; }
  const hal::linux_can::CanBoard& board() const { return *board_; }
  const hal::linux_can::FaultyCanTransport& link() const { return *faulty_; }
  bool detected() const { return detected_; }
  std::uint32_t detection_jiffy() const { return detection_jiffy_; }  // the board's jiffy
  firmware::ValveCommand valve_at_detection() const { return valve_at_detection_; }
  bool link_fault_seen() const { return link_fault_seen_; }
  // The board's first jiffy that could see the link fault.
  std::uint32_t link_fault_board_jiffy() const { return link_fault_board_jiffy_; }
  std::uint32_t plant_jiffy() const { return plant_jiffy_; }
  std::uint32_t answers() const { return answers_; }
  std::uint32_t watchdog_closes() const { return watchdog_closes_; }
  std::uint32_t stale_jiffies() const { return stale_jiffies_; }
  // The most the silo released in one plant jiffy so far (full flow): what one lost command costs.
  double max_release_per_jiffy_kg() const { return max_release_per_jiffy_kg_; }

 private:
  // Reads what the board sent; runs the board until the 0x220 carrying `counter` came or one jiffy
  // of wall time passed.
  bool await_answer(std::uint16_t counter, hal::can::ValveCommandMessage& answer) {
    using Clock = std::chrono::steady_clock;
    const auto deadline = Clock::now() + std::chrono::milliseconds(kAnswerWaitMs);
    bool answered = false;
    for (;;) {
      hal::can::CanFrame frame;
      while (plant_link_->receive(frame, 0) == 1) {
        hal::can::ValveCommandMessage m;
        if (hal::can::decode(frame, m) && m.counter == counter) {
          answer = m;
          answered = true;
        }
      }
      if (answered) return true;
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
      if (left <= 0) return false;
      const std::uint32_t jiffy_before = board_->jiffy();
      note(board_->poll(int(left)));
      if (faulty_->link_fault_active() && !link_fault_seen_) {  // it took hold inside this poll
        link_fault_seen_ = true;
        link_fault_board_jiffy_ = jiffy_before;
      }
    }
  }

  void note(hal::linux_can::CanBoard::Event event) {
    using Event = hal::linux_can::CanBoard::Event;
    if (event == Event::closed) throw std::runtime_error("udp link closed");
    if (event == Event::stale_jiffy) ++stale_jiffies_;
    if (event != Event::jiffy && event != Event::stale_jiffy && event != Event::bus_off) return;
    if (!detected_ && indicator_.fault() != firmware::Fault::none) {
      detected_ = true;
      detection_jiffy_ = board_->jiffy() - 1;
      valve_at_detection_ = board_->last_outputs().valve;
    }
  }

  // Two udp transports on free loopback ports, each the other's peer.
  void open_links() {
    static std::uint32_t opened = 0;
    for (int attempt = 0; attempt < 50 && !plant_link_; ++attempt) {
      const std::uint16_t a = std::uint16_t(21000 + ((std::uint32_t(::getpid()) * 97u + 2u * opened++) % 40000u));
      const std::uint16_t b = std::uint16_t(a + 1);
      try {
        auto board = hal::linux_can::open_can_transport(udp(a, b));
        auto plant = hal::linux_can::open_can_transport(udp(b, a));
        board_link_ = std::move(board);
        plant_link_ = std::move(plant);
      } catch (const std::runtime_error&) {
        // taken by another process: try the next pair
      }
    }
    if (!plant_link_) throw std::runtime_error("no free udp port pair on 127.0.0.1");
  }

  static std::string udp(std::uint16_t bind, std::uint16_t peer) {
    return "udp:" + std::to_string(bind) + "@127.0.0.1:" + std::to_string(peer);
  }

  sim::Plant plant_;
  firmware::Indicator indicator_;
  StringConsole console_;
  std::unique_ptr<hal::linux_can::CanTransport> board_link_, plant_link_;
  std::unique_ptr<hal::linux_can::FaultyCanTransport> faulty_;
  std::unique_ptr<hal::linux_can::CanBoard> board_;
  std::uint32_t plant_jiffy_ = 0;
  std::uint32_t last_answer_jiffy_ = 0;
  bool watchdog_closed_ = false;
  std::uint32_t answers_ = 0, watchdog_closes_ = 0, stale_jiffies_ = 0;
  bool detected_ = false;
  std::uint32_t detection_jiffy_ = 0;
  firmware::ValveCommand valve_at_detection_ = firmware::ValveCommand::closed;
  bool link_fault_seen_ = false;
  std::uint32_t link_fault_board_jiffy_ = 0;
  double max_release_per_jiffy_kg_ = 0.0;
};

}  // namespace dynweigh::testing
