#pragma once
// The indicator as a node on the plant link (docs/can-protocol.md), written once for every board
// that carries the frames: the Linux board (SocketCAN, udp, slcan) and the Cortex-M image (SLCAN
// on a UART) are adapters around it that bring a transport and a clock.
//
// One jiffy per 0x190 sample, through hal::run_one_jiffy; each is answered with exactly one 0x220
// valve command carrying the sample's counter, then the 0x181 status. Once the indicator has first
// commanded the discharge gate open, every answer is preceded by a 0x228 gate command with the same
// counter (a plant without a gate node never hears one; 0x1A8 feedback is read whenever it comes);
// likewise each ingredient valve's 0x221..0x227 once a batch has first opened it (0x1A1..0x1A7 read
// whenever they come). Samples are put in order by
// their counter (sample_sequence.hpp): a duplicate runs no jiffy, a late one is discarded, a lost
// one is a jiffy without a sample and without an answer (the plant no longer waits for it). When
// the board's clock says the link has gone quiet, the board asks for a jiffy without a sample; the
// indicator then sees the link `silent` if nothing at all came from the plant since the last
// jiffy, `bus_off` whenever the transport says so.
#include <cstdint>

#include "dynweigh/firmware/indicator.hpp"
#include "dynweigh/hal/can/can_frame.hpp"
#include "dynweigh/hal/can/sample_sequence.hpp"
#include "dynweigh/hal/control_loop.hpp"
#include "dynweigh/hal/ports.hpp"

namespace dynweigh::hal::can {

// The board's side of the link: where the node's frames go, and whether the bus is still there.
class CanLink {
 public:
  virtual void send(const CanFrame& frame) = 0;
  virtual bool bus_off() const { return false; }

 protected:
  ~CanLink() = default;
};

// The load cell as the last 0x190 frame: fresh once, then stale until the next one.
class CanLoadCell final : public LoadCellPort {
 public:
  void deliver(const firmware::LoadCellInput& sample) {
    sample_ = sample;
    sample_.fresh = true;
  }
  void set_link(firmware::LinkStatus link) { sample_.link = link; }
  firmware::LoadCellInput read_sample() override {
    firmware::LoadCellInput out = sample_;
    sample_.fresh = false;
    return out;
  }
  std::int32_t last_raw_counts() const { return sample_.raw_counts; }

 private:
  firmware::LoadCellInput sample_{0, 0, 0, false, firmware::LinkStatus::ok};
};

// The valve as 0x220 out (sent by the node, with the answered counter) and 0x1A0 in.
class CanValve final : public ValvePort {
 public:
  void command(firmware::ValveCommand command, std::uint8_t delay_100us) override {
    command_ = command;
    delay_100us_ = delay_100us;
  }
  firmware::ValvePosition position() const override { return position_; }
  void deliver_position(firmware::ValvePosition position) { position_ = position; }
  firmware::ValveCommand last_command() const { return command_; }
  std::uint8_t last_delay_100us() const { return delay_100us_; }

 private:
  firmware::ValveCommand command_ = firmware::ValveCommand::closed;
  std::uint8_t delay_100us_ = 0;
  firmware::ValvePosition position_ = firmware::ValvePosition::closed;
};

// The discharge gate as 0x228 out (sent by the node, once the gate has first been opened) and 0x1A8 in.
class CanGate final : public GatePort {
 public:
  void command(firmware::GateCommand command) override {
    command_ = command;
    if (command != firmware::GateCommand::closed) commanded_ = true;
  }
  firmware::GatePosition position() const override { return position_; }
  void deliver_position(firmware::GatePosition position) { position_ = position; }
  std::uint8_t faults() const override { return faults_; }
  void deliver_faults(std::uint8_t faults) { faults_ = faults; }
  firmware::GateCommand last_command() const { return command_; }
  // The gate has been opened at least once: from then on its command goes out every jiffy.
  bool commanded() const { return commanded_; }

 private:
  firmware::GateCommand command_ = firmware::GateCommand::closed;
  firmware::GatePosition position_ = firmware::GatePosition::closed;
  std::uint8_t faults_ = 0;
  bool commanded_ = false;
};

// A batch's ingredient valves 1..7 as 0x221..0x227 out (sent by the node for each valve once it has
// first been commanded open, with the 0x220 payload) and 0x1A1..0x1A7 in. A valve whose feedback
// has been heard is there.
class CanIngredientValves final : public IngredientValvesPort {
 public:
  static constexpr std::uint8_t kValves = 8;  // ingredient 0's is CanValve
  std::uint8_t present() const override { return present_; }
  void command(std::uint8_t ingredient, firmware::ValveCommand command, std::uint8_t delay_100us) override {
    ingredient_ = ingredient < kValves ? ingredient : 0;
    command_ = command;
    delay_100us_ = delay_100us;
    if (ingredient_ != 0 && command != firmware::ValveCommand::closed) commanded_ |= std::uint8_t(1u << ingredient_);
  }
  firmware::ValvePosition position(std::uint8_t ingredient) const override {
    return ingredient < kValves ? position_[ingredient] : firmware::ValvePosition::closed;
  }
  void deliver_position(std::uint8_t ingredient, firmware::ValvePosition position) {
    position_[ingredient] = position;
    present_ |= std::uint8_t(1u << ingredient);
  }
  // Bit i: valve i has been commanded open at least once; from then on its command goes out every jiffy.
  std::uint8_t commanded() const { return commanded_; }
  firmware::ValveCommand command_of(std::uint8_t ingredient) const {
    return ingredient == ingredient_ ? command_ : firmware::ValveCommand::closed;
  }
  std::uint8_t delay_of(std::uint8_t ingredient) const { return ingredient == ingredient_ ? delay_100us_ : 0; }
  // Every valve commanded closed (the indicator goes away).
  void close_all() { command(0, firmware::ValveCommand::closed, 0); }

 private:
  std::uint8_t ingredient_ = 0;
  firmware::ValveCommand command_ = firmware::ValveCommand::closed;
  std::uint8_t delay_100us_ = 0;
  firmware::ValvePosition position_[kValves] = {};
  std::uint8_t present_ = 0x01;
  std::uint8_t commanded_ = 0;
};

struct IndicatorNodeOptions {
  SettingsStore* settings = nullptr;  // nothing persists without one
  // A 0x701 heartbeat after every this many jiffies; 0: the board sends heartbeats by its clock.
  std::uint32_t heartbeat_jiffies = 0;
  StepProbe* probe = nullptr;  // marks Indicator::step for a board that measures it
};

class IndicatorNode {
 public:
  // What a received frame did. `sample`: a jiffy ran on it (after any for lost samples);
  // `repeated_sample`: a duplicate or late 0x190, no jiffy; `ignored`: our own frames echoed by a
  // bus, other nodes' heartbeats, malformed frames.
  enum class Heard { sample, repeated_sample, valve_position, gate_position, ingredient_position, plant_stopped, ignored };

  IndicatorNode(firmware::Indicator& indicator, ConsolePort& console, CanLink& link,
                const IndicatorNodeOptions& options = {});
  IndicatorNode(const IndicatorNode&) = delete;
  IndicatorNode& operator=(const IndicatorNode&) = delete;

  Heard receive(const CanFrame& frame);
  // A jiffy without a sample: the board's clock says the sample is late, or the bus went off.
  void run_without_sample();
  void send_heartbeat(std::uint8_t nmt_state);
  // The indicator goes away: a valve (or gate) it left open is commanded closed at once (not left to the
  // valve module's 50 ms watchdog), then the heartbeat says NMT stopped.
  void leave();

  // A frame from the plant's nodes came since the start, or since forget_plant().
  bool plant_heard() const { return plant_heard_; }
  // The plant left in order (its NMT stopped): what comes next is a new plant.
  void forget_plant() { plant_heard_ = false; }

  std::uint32_t jiffy() const { return jiffy_; }
  const firmware::Outputs& last_outputs() const { return record_.outputs; }
  const JiffyRecord& last_record() const { return record_; }
  // Every jiffy from the next on also goes to `recorder` (nullptr: no more).
  void record_to(JiffyRecorder* recorder) { ports_.recorder = recorder; }
  std::int32_t last_raw_counts() const { return load_cell_.last_raw_counts(); }
  const SampleSequence& samples() const { return sequence_; }

 private:
  Heard on_sample(const CanFrame& frame);
  // `answer`: send the 0x220/0x181 pair (not for a jiffy standing in for a lost sample).
  void run_jiffy(firmware::LinkStatus link, bool answer);
  firmware::LinkStatus link_status(bool heard) const;
  void send_ingredient_commands(std::uint16_t counter);

  firmware::Indicator& indicator_;
  CanLink& link_;
  std::uint32_t heartbeat_jiffies_;
  CanLoadCell load_cell_;
  CanValve valve_;
  CanGate gate_;
  CanIngredientValves ingredients_;
  Ports ports_;
  SampleSequence sequence_;
  bool plant_heard_ = false;
  bool heard_since_jiffy_ = false;  // a frame from the plant came since the last jiffy
  std::uint32_t jiffy_ = 0;
  JiffyRecord record_{};
};

}  // namespace dynweigh::hal::can
