#pragma once
// The Linux CAN board (docs/can-protocol.md): the portable indicator node (hal/can/indicator_node.hpp)
// over a Linux transport, with a timerfd for its clock. The node runs one jiffy per 0x190 load-cell
// sample and answers each with exactly one 0x220 valve command carrying the sample's counter, then
// its 0x181 status; a 0x700+1 heartbeat goes out every 10 jiffies and whenever the link is quiet for 100 ms.
// Lockstep (a plant that waits for the answer) and real time (modules sending every 10 ms) are the
// same loop; in real time a timerfd also runs a jiffy with `fresh = false` when a sample is more
// than 25 ms late, so a dead load-cell module becomes a fault instead of a frozen indicator. In
// lockstep the same timer runs such jiffies once a plant that was heard has said nothing for 1 s
// of wall time (a lockstep plant answers in microseconds; one that stops without its NMT-stopped
// heartbeat is dead), so a silent bus becomes a fault there too.
//
// The link's faults (sample order, lost samples, `silent` and `bus_off`) are the node's; this board
// adds that a transport that goes bus-off gets a jiffy at once.
#include <cstdint>

#include "dynweigh/firmware/indicator.hpp"
#include "dynweigh/hal/can/indicator_node.hpp"
#include "dynweigh/hal/linux/can_transport.hpp"
#include "dynweigh/hal/ports.hpp"

namespace dynweigh::hal::linux_can {

class CanBoard {
 public:
  // plant_stopped: the load-cell module's heartbeat said NMT stopped (dynweigh plant is leaving).
  // bus_off: the transport went bus-off and a jiffy ran to report it.
  enum class Event { jiffy, stale_jiffy, quiet, closed, plant_stopped, bus_off };

  CanBoard(CanTransport& transport, firmware::Indicator& indicator, ConsolePort& console,
           SettingsStore* store = nullptr, bool realtime = false);
  ~CanBoard();
  CanBoard(const CanBoard&) = delete;
  CanBoard& operator=(const CanBoard&) = delete;

  // Waits up to `timeout_ms` for the next sample and runs one jiffy on it. `quiet`: nothing came
  // (a heartbeat has gone out); `closed`: the link ended.
  Event poll(int timeout_ms);
  void send_heartbeat(std::uint8_t nmt_state);
  // The indicator goes away (SIGTERM, end of input): a valve it left open is commanded closed at
  // once, not left to the valve module's 50 ms watchdog, then the heartbeat says NMT stopped.
  void leave();

  std::uint32_t jiffy() const { return node_.jiffy(); }
  const firmware::Outputs& last_outputs() const { return node_.last_outputs(); }
  const JiffyRecord& last_record() const { return node_.last_record(); }
  // Every jiffy from the next on also goes to `recorder` (nullptr: no more); `dynweigh-fw --record`.
  void record_to(JiffyRecorder* recorder) { node_.record_to(recorder); }
  std::uint32_t frames_ignored() const { return ignored_; }
  std::int32_t last_raw_counts() const { return node_.last_raw_counts(); }
  const can::SampleSequence& samples() const { return node_.samples(); }

  static constexpr int kStaleAfterMs = 25;         // real time: 2.5 periods without a sample
  static constexpr int kLockstepSilenceMs = 1000;  // lockstep: a plant this long quiet is dead

 private:
  // The transport as the node's link.
  class Link final : public can::CanLink {
   public:
    explicit Link(CanTransport& transport) : transport_(transport) {}
    void send(const CanFrame& frame) override { transport_.send(frame); }
    bool bus_off() const override { return transport_.bus_off(); }

   private:
    CanTransport& transport_;
  };

  void arm_stale_timer(int first_ms);
  void disarm_stale_timer();

  CanTransport& transport_;
  Link link_;
  can::IndicatorNode node_;
  bool realtime_ = false;
  int timer_fd_ = -1;
  bool bus_off_reported_ = false;
  std::uint32_t ignored_ = 0;
};

}  // namespace dynweigh::hal::linux_can
