#include "dynweigh/hal/linux/can_board.hpp"

#include <poll.h>
#include <sys/timerfd.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "dynweigh/hal/can/protocol.hpp"
#include "dynweigh/hal/control_loop.hpp"

namespace dynweigh::hal::linux_can {
namespace {
constexpr int kJiffyMs = 10;
constexpr std::uint32_t kHeartbeatJiffies = 10;  // 100 ms

// Our own frames, echoed by a bus, prove nothing about the plant's side of it.
bool from_the_plant(const CanFrame& frame) {
  switch (can::classify(frame)) {
    case can::MessageKind::valve_command:
    case can::MessageKind::indicator_status:
      return false;
    case can::MessageKind::heartbeat:
      return frame.id != can::kIdHeartbeatBase + can::kNodeIndicator;
    default:
      return true;
  }
}
}  // namespace

CanBoard::CanBoard(CanTransport& transport, firmware::Indicator& indicator, ConsolePort& console,
                   SettingsStore* store, bool realtime)
    : transport_(transport), indicator_(indicator), console_(console), store_(store), realtime_(realtime) {
  timer_fd_ = ::timerfd_create(CLOCK_MONOTONIC, TFD_CLOEXEC | TFD_NONBLOCK);
  if (timer_fd_ < 0) throw std::runtime_error("timerfd_create: " + std::string(std::strerror(errno)));
  if (realtime) arm_stale_timer(kStaleAfterMs);  // lockstep: once the plant has been heard
}

CanBoard::~CanBoard() { ::close(timer_fd_); }

void CanBoard::disarm_stale_timer() {
  const itimerspec off{};
  ::timerfd_settime(timer_fd_, 0, &off, nullptr);
}

void CanBoard::arm_stale_timer(int first_ms) {
  itimerspec spec{};
  spec.it_value.tv_sec = first_ms / 1000;
  spec.it_value.tv_nsec = long(first_ms % 1000) * 1000000L;
  spec.it_interval.tv_nsec = long(kJiffyMs) * 1000000L;
  ::timerfd_settime(timer_fd_, 0, &spec, nullptr);
}

void CanBoard::send_heartbeat(std::uint8_t nmt_state) {
  transport_.send(can::encode(can::HeartbeatMessage{can::kNodeIndicator, nmt_state}));
}

void CanBoard::leave() {
  if (valve_.last_command() != firmware::ValveCommand::closed) {
    valve_.command(firmware::ValveCommand::closed, 0);
    transport_.send(can::encode(can::ValveCommandMessage{static_cast<std::uint8_t>(firmware::ValveCommand::closed), 0,
                                                         record_.outputs.answered_counter}));
  }
  send_heartbeat(can::kNmtStopped);
}

firmware::LinkStatus CanBoard::link_status(bool heard) const {
  if (transport_.bus_off()) return firmware::LinkStatus::bus_off;
  return heard ? firmware::LinkStatus::ok : firmware::LinkStatus::silent;
}

void CanBoard::run_jiffy_without_sample() {
  run_jiffy(link_status(heard_since_jiffy_));
  sequence_.stood_in();
}

void CanBoard::run_jiffy(firmware::LinkStatus link, bool answer) {
  load_cell_.set_link(link);
  heard_since_jiffy_ = false;
  Ports ports{load_cell_, valve_, console_, store_, save_report_, recorder_};
  record_ = run_one_jiffy(indicator_, ports, jiffy_);
  const firmware::Outputs& outputs = record_.outputs;
  save_report_ = ports.save_report;
  if (answer) {
    // Exactly one 0x220 per sample: the lockstep acknowledgement and the valve module's watchdog.
    transport_.send(can::encode(can::ValveCommandMessage{static_cast<std::uint8_t>(valve_.last_command()),
                                                         valve_.last_delay_100us(), outputs.answered_counter}));
    transport_.send(can::encode(can::IndicatorStatusMessage{outputs.weight_100mg,
                                                            static_cast<std::uint8_t>(outputs.state),
                                                            static_cast<std::uint8_t>(outputs.valve),
                                                            outputs.answered_counter}));
  }
  ++jiffy_;
  if (jiffy_ % kHeartbeatJiffies == 0) send_heartbeat(can::kNmtOperational);
}

CanBoard::Event CanBoard::poll(int timeout_ms) {
  for (;;) {
    // Bus-off is reported in a jiffy of its own, at once: no sample may come to run one.
    if (transport_.bus_off() != bus_off_reported_) {
      bus_off_reported_ = !bus_off_reported_;
      if (bus_off_reported_) {
        run_jiffy_without_sample();
        return Event::bus_off;
      }
    }
    CanFrame frame;
    int got = 0;
    if (transport_.has_buffered_input()) {
      got = transport_.receive(frame, 0);
    } else {
      pollfd fds[2] = {{transport_.fd(), POLLIN, 0}, {timer_fd_, POLLIN, 0}};
      const int ready = ::poll(fds, 2, timeout_ms);
      if (ready < 0 && errno == EINTR) continue;
      if (ready == 0) {
        send_heartbeat(can::kNmtOperational);
        return Event::quiet;
      }
      if (fds[1].revents & POLLIN) {
        std::uint64_t expirations = 0;
        if (::read(timer_fd_, &expirations, sizeof expirations) == ssize_t(sizeof expirations) && expirations > 0) {
          run_jiffy_without_sample();  // the load cell is late: the indicator sees fresh = false
          return Event::stale_jiffy;
        }
      }
      if (fds[0].revents & (POLLIN | POLLHUP | POLLERR)) got = transport_.receive(frame, 0);
    }
    if (got < 0) return Event::closed;
    if (got == 0) continue;
    if (from_the_plant(frame)) {
      heard_since_jiffy_ = true;
      if (!plant_heard_ && !realtime_) arm_stale_timer(kLockstepSilenceMs);
      plant_heard_ = true;
    }
    switch (can::classify(frame)) {
      case can::MessageKind::load_cell_sample: {
        can::LoadCellSampleMessage m;
        if (!can::decode(frame, m)) break;
        const can::SampleSequence::Arrival arrival = sequence_.arrive(m.counter);
        if (!arrival.accept) continue;  // the same sample again, or one the indicator is already past
        for (std::uint16_t i = 0; i < arrival.missing; ++i) run_jiffy(link_status(true), /*answer=*/false);
        load_cell_.deliver(firmware::LoadCellInput{m.raw_counts, m.counter, m.status, true, firmware::LinkStatus::ok});
        last_raw_ = m.raw_counts;
        run_jiffy(link_status(true));
        arm_stale_timer(realtime_ ? kStaleAfterMs : kLockstepSilenceMs);
        return Event::jiffy;
      }
      case can::MessageKind::valve_feedback: {
        can::ValveFeedbackMessage m;
        if (can::decode(frame, m)) {
          valve_.deliver_position(static_cast<firmware::ValvePosition>(m.position));
          continue;
        }
        break;
      }
      case can::MessageKind::heartbeat: {
        can::HeartbeatMessage m;
        if (can::decode(frame, m) && m.node == can::kNodeLoadCell && m.nmt_state == can::kNmtStopped) {
          sequence_.reset();  // a plant that comes back counts afresh
          if (!realtime_) {   // an orderly stop is no silence; the next plant's frame re-arms
            disarm_stale_timer();
            plant_heard_ = false;
          }
          return Event::plant_stopped;
        }
        break;
      }
      default:
        break;
    }
    ++ignored_;  // our own frames echoed back, other nodes' heartbeats, malformed frames
  }
}

}  // namespace dynweigh::hal::linux_can
