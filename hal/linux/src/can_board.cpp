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
constexpr int kStaleAfterMs = 25;   // 2.5 periods without a sample: run a jiffy without one
constexpr int kJiffyMs = 10;
constexpr std::uint32_t kHeartbeatJiffies = 10;  // 100 ms
}  // namespace

CanBoard::CanBoard(CanTransport& transport, firmware::Indicator& indicator, ConsolePort& console,
                   SettingsStore* store, bool realtime)
    : transport_(transport), indicator_(indicator), console_(console), store_(store) {
  if (realtime) {
    timer_fd_ = ::timerfd_create(CLOCK_MONOTONIC, TFD_CLOEXEC | TFD_NONBLOCK);
    if (timer_fd_ < 0) throw std::runtime_error("timerfd_create: " + std::string(std::strerror(errno)));
    arm_stale_timer(kStaleAfterMs);
  }
}

CanBoard::~CanBoard() {
  if (timer_fd_ >= 0) ::close(timer_fd_);
}

void CanBoard::arm_stale_timer(int first_ms) {
  if (timer_fd_ < 0) return;
  itimerspec spec{};
  spec.it_value.tv_sec = first_ms / 1000;
  spec.it_value.tv_nsec = long(first_ms % 1000) * 1000000L;
  spec.it_interval.tv_nsec = long(kJiffyMs) * 1000000L;
  ::timerfd_settime(timer_fd_, 0, &spec, nullptr);
}

void CanBoard::send_heartbeat(std::uint8_t nmt_state) {
  transport_.send(can::encode(can::HeartbeatMessage{can::kNodeIndicator, nmt_state}));
}

void CanBoard::run_jiffy() {
  Ports ports{load_cell_, valve_, console_, store_};
  outputs_ = run_one_jiffy(indicator_, ports, jiffy_);
  // Exactly one 0x220 per jiffy: the lockstep acknowledgement and the valve module's watchdog.
  transport_.send(can::encode(can::ValveCommandMessage{static_cast<std::uint8_t>(valve_.last_command()),
                                                       valve_.last_delay_100us(), outputs_.answered_counter}));
  transport_.send(can::encode(can::IndicatorStatusMessage{outputs_.weight_100mg,
                                                          static_cast<std::uint8_t>(outputs_.state),
                                                          static_cast<std::uint8_t>(outputs_.valve),
                                                          outputs_.answered_counter}));
  ++jiffy_;
  if (jiffy_ % kHeartbeatJiffies == 0) send_heartbeat(can::kNmtOperational);
}

CanBoard::Event CanBoard::poll(int timeout_ms) {
  for (;;) {
    CanFrame frame;
    int got = 0;
    if (transport_.has_buffered_input()) {
      got = transport_.receive(frame, 0);
    } else {
      pollfd fds[2] = {{transport_.fd(), POLLIN, 0}, {timer_fd_, POLLIN, 0}};
      const int ready = ::poll(fds, timer_fd_ >= 0 ? 2 : 1, timeout_ms);
      if (ready < 0 && errno == EINTR) continue;
      if (ready == 0) {
        send_heartbeat(can::kNmtOperational);
        return Event::quiet;
      }
      if (timer_fd_ >= 0 && (fds[1].revents & POLLIN)) {
        std::uint64_t expirations = 0;
        if (::read(timer_fd_, &expirations, sizeof expirations) == ssize_t(sizeof expirations) && expirations > 0) {
          run_jiffy();  // the load cell is late: the indicator sees fresh = false
          return Event::stale_jiffy;
        }
      }
      if (fds[0].revents & (POLLIN | POLLHUP | POLLERR)) got = transport_.receive(frame, 0);
    }
    if (got < 0) return Event::closed;
    if (got == 0) continue;
    switch (can::classify(frame)) {
      case can::MessageKind::load_cell_sample: {
        can::LoadCellSampleMessage m;
        if (!can::decode(frame, m)) break;
        load_cell_.deliver(firmware::LoadCellInput{m.raw_counts, m.counter, m.status, true});
        last_raw_ = m.raw_counts;
        run_jiffy();
        arm_stale_timer(kStaleAfterMs);
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
