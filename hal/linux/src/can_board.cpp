#include "dynweigh/hal/linux/can_board.hpp"

#include <poll.h>
#include <sys/timerfd.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "dynweigh/hal/can/protocol.hpp"

namespace dynweigh::hal::linux_can {
namespace {
constexpr int kJiffyMs = 10;
constexpr std::uint32_t kHeartbeatJiffies = 10;  // 100 ms
}  // namespace

CanBoard::CanBoard(CanTransport& transport, firmware::Indicator& indicator, ConsolePort& console,
                   SettingsStore* store, bool realtime)
    : transport_(transport),
      link_(transport),
      node_(indicator, console, link_, can::IndicatorNodeOptions{store, kHeartbeatJiffies, nullptr}),
      realtime_(realtime) {
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

void CanBoard::send_heartbeat(std::uint8_t nmt_state) { node_.send_heartbeat(nmt_state); }

void CanBoard::leave() { node_.leave(); }

CanBoard::Event CanBoard::poll(int timeout_ms) {
  for (;;) {
    // Bus-off is reported in a jiffy of its own, at once: no sample may come to run one.
    if (transport_.bus_off() != bus_off_reported_) {
      bus_off_reported_ = !bus_off_reported_;
      if (bus_off_reported_) {
        node_.run_without_sample();
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
          node_.run_without_sample();  // the load cell is late: the indicator sees fresh = false
          return Event::stale_jiffy;
        }
      }
      if (fds[0].revents & (POLLIN | POLLHUP | POLLERR)) got = transport_.receive(frame, 0);
    }
    if (got < 0) return Event::closed;
    if (got == 0) continue;
    const bool plant_was_heard = node_.plant_heard();
    switch (node_.receive(frame)) {
      case can::IndicatorNode::Heard::sample:
        arm_stale_timer(realtime_ ? kStaleAfterMs : kLockstepSilenceMs);
        return Event::jiffy;
      case can::IndicatorNode::Heard::plant_stopped:
        if (!realtime_) {  // an orderly stop is no silence; the next plant's frame re-arms
          disarm_stale_timer();
          node_.forget_plant();
        }
        return Event::plant_stopped;
      case can::IndicatorNode::Heard::repeated_sample:
      case can::IndicatorNode::Heard::valve_position:
      case can::IndicatorNode::Heard::gate_position:
      case can::IndicatorNode::Heard::ingredient_position:
        break;
      case can::IndicatorNode::Heard::ignored:
        ++ignored_;  // our own frames echoed back, other nodes' heartbeats, malformed frames
        break;
    }
    if (!plant_was_heard && node_.plant_heard() && !realtime_) arm_stale_timer(kLockstepSilenceMs);
  }
}

}  // namespace dynweigh::hal::linux_can
