#pragma once
// Fault injection on the CAN link (ArduPilot SITL's habit of breaking things at the driver
// edge): a CanTransport around another that drops, duplicates and delays (reorders) frames, at
// chosen frame indices or with a seeded probability, in either direction, and that can go silent
// or bus-off from a chosen load-cell sample on. Frame indices count the frames that passed through
// in that direction (0-based); a link fault takes hold right after the received 0x190 frame number
// `link_fault_at_sample - 1` (0: from the start), so nothing of the plant's jiffy
// `link_fault_at_sample` arrives (on a CAN link the sample count is the plant's jiffy). What the indicator makes of each is the CAN board's business
// (hal/can/sample_sequence.hpp, can_board.hpp), not this wrapper's.
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "dynweigh/hal/linux/can_transport.hpp"

namespace dynweigh::hal::linux_can {

enum class FrameFault : std::uint8_t {
  none,
  drop,       // lost on the wire
  duplicate,  // delivered twice in a row
  delay,      // held back and delivered after `delay_frames` later frames (1: swapped with the next)
};

enum class LinkFault : std::uint8_t {
  none,
  silence,  // from then on nothing arrives and what is sent goes nowhere (send still succeeds)
  bus_off,  // from then on nothing arrives, send fails and bus_off() says so
};

enum class Direction : std::uint8_t { received, sent };

struct ChosenFrameFault {
  Direction direction = Direction::received;
  std::uint32_t index = 0;  // the index-th frame in that direction
  FrameFault fault = FrameFault::none;
};

struct CanFaultPlan {
  // Random faults, each frame independently (drop first, then duplicate, then delay by one frame).
  std::uint64_t seed = 1;
  double drop_probability = 0.0;
  double duplicate_probability = 0.0;
  double reorder_probability = 0.0;
  bool random_on_received = true;
  bool random_on_sent = true;
  std::vector<ChosenFrameFault> chosen;  // exact faults at exact frames (set up before the run)
  std::uint32_t delay_frames = 1;        // how far a chosen `delay` holds its frame back
  LinkFault link_fault = LinkFault::none;
  std::uint32_t link_fault_at_sample = 0;
};

class FaultyCanTransport final : public CanTransport {
 public:
  FaultyCanTransport(CanTransport& inner, CanFaultPlan plan);

  bool send(const CanFrame& frame) override;
  int receive(CanFrame& frame, int timeout_ms) override;
  const std::string& name() const override { return name_; }
  int fd() const override { return inner_.fd(); }
  bool has_buffered_input() const override;
  bool bus_off() const override;

  struct Counts {
    std::uint32_t frames = 0, dropped = 0, duplicated = 0, delayed = 0;
  };
  const Counts& received_counts() const { return received_; }
  const Counts& sent_counts() const { return sent_; }
  std::uint32_t samples_received() const { return samples_; }  // 0x190 frames that came in
  bool link_fault_active() const { return link_fault_active_; }

 private:
  static constexpr std::size_t kQueue = 16;
  struct Held {
    CanFrame frame;
    std::uint32_t frames_to_wait = 0;
  };
  // Frames ready to hand out (duplicates, released delayed frames) and frames held back: fixed
  // rings, nothing allocated per frame. A full ring passes the frame straight through.
  struct Queue {
    Held items[kQueue];
    std::size_t count = 0;
    bool push(const CanFrame& frame, std::uint32_t wait);
    CanFrame pop_front();
  };

  FrameFault decide(Direction direction, std::uint32_t index);
  bool chance(double probability);
  // One more frame went by in `direction`: delayed frames whose wait is over become ready.
  void count_down(Queue& held, Queue& ready);
  int receive_inner(CanFrame& frame, int timeout_ms);
  bool deliver_sent(const CanFrame& frame);

  CanTransport& inner_;
  CanFaultPlan plan_;
  std::string name_;
  std::mt19937_64 random_;
  std::uniform_real_distribution<double> uniform_{0.0, 1.0};
  Queue ready_in_, held_in_, held_out_;
  Counts received_, sent_;
  std::uint32_t samples_ = 0;
  bool link_fault_active_ = false;
};

}  // namespace dynweigh::hal::linux_can
