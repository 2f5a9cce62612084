#pragma once
// The Linux CAN board (docs/can-protocol.md): the indicator runs one jiffy per 0x190 load-cell sample and
// answers each with exactly one 0x220 valve command carrying the sample's counter, then its 0x181
// status; a 0x700+1 heartbeat goes out every 10 jiffies and whenever the link is quiet for 100 ms.
// Lockstep (a plant that waits for the answer) and real time (modules sending every 10 ms) are the
// same loop; in real time a timerfd also runs a jiffy with `fresh = false` when a sample is more
// than 25 ms late, so a dead load-cell module becomes a fault instead of a frozen indicator. In
// lockstep the same timer runs such jiffies once a plant that was heard has said nothing for 1 s
// of wall time (a lockstep plant answers in microseconds; one that stops without its NMT-stopped
// heartbeat is dead), so a silent bus becomes a fault there too.
//
// The link's faults: samples are put in order by their counter (hal/can/
// sample_sequence.hpp: a duplicate runs no jiffy, a late one is discarded, a lost one is a jiffy
// without a sample); each jiffy tells the indicator the link's status through the load cell's
// sample (firmware::LinkStatus): `silent` when nothing at all came from the plant since the last
// jiffy, `bus_off` when the transport says so. A transport that goes bus-off gets a jiffy at once.
#include <cstdint>

#include "dynweigh/firmware/indicator.hpp"
#include "dynweigh/hal/can/sample_sequence.hpp"
#include "dynweigh/hal/jiffy_record.hpp"
#include "dynweigh/hal/linux/can_transport.hpp"
#include "dynweigh/hal/ports.hpp"

namespace dynweigh::hal::linux_can {

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

 private:
  firmware::LoadCellInput sample_{0, 0, 0, false, firmware::LinkStatus::ok};
};

// The valve as 0x220 out (sent by the board, with the answered counter) and 0x1A0 in.
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

  // Every jiffy from the next on also goes to `recorder` (nullptr: no more); `dynweigh-fw --record`.
  void record_to(JiffyRecorder* recorder) { recorder_ = recorder; }

  std::uint32_t jiffy() const { return jiffy_; }
  const firmware::Outputs& last_outputs() const { return record_.outputs; }
  const JiffyRecord& last_record() const { return record_; }
  std::uint32_t frames_ignored() const { return ignored_; }
  std::int32_t last_raw_counts() const { return last_raw_; }
  const can::SampleSequence& samples() const { return sequence_; }

  static constexpr int kStaleAfterMs = 25;         // real time: 2.5 periods without a sample
  static constexpr int kLockstepSilenceMs = 1000;  // lockstep: a plant this long quiet is dead

 private:
  // `answer`: send the 0x220/0x181 pair (not for a jiffy standing in for a lost sample: the plant
  // is no longer waiting for it).
  void run_jiffy(firmware::LinkStatus link, bool answer = true);
  void run_jiffy_without_sample();
  firmware::LinkStatus link_status(bool heard) const;
  void arm_stale_timer(int first_ms);
  void disarm_stale_timer();

  CanTransport& transport_;
  firmware::Indicator& indicator_;
  ConsolePort& console_;
  SettingsStore* store_;
  CanLoadCell load_cell_;
  CanValve valve_;
  can::SampleSequence sequence_;
  bool realtime_ = false;
  int timer_fd_ = -1;
  bool plant_heard_ = false;        // a frame from the plant's nodes ever came (lockstep: arms the timer)
  bool heard_since_jiffy_ = false;  // one came since the last jiffy
  bool bus_off_reported_ = false;
  std::uint32_t jiffy_ = 0;
  std::uint32_t ignored_ = 0;
  std::int32_t last_raw_ = 0;
  firmware::SettingsSave save_report_ = firmware::SettingsSave::none;
  JiffyRecorder* recorder_ = nullptr;
  JiffyRecord record_;
};

}  // namespace dynweigh::hal::linux_can
