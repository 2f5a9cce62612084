// The Linux transports carry the same frames (udp on loopback, slcan on a pty), and the CAN board
// keeps the lockstep contract: one jiffy per 0x190 sample, one 0x220 per sample with its counter.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <cstdlib>
#include <memory>
#include <stdexcept>
#include <string>

#include "dynweigh/hal/can/protocol.hpp"
#include "dynweigh/hal/can/slcan.hpp"
#include "dynweigh/hal/host/simulated_plant_ports.hpp"
#include "dynweigh/hal/linux/can_board.hpp"
#include "dynweigh/hal/linux/can_transport.hpp"
#include "dynweigh/sim/plant.hpp"
#include "dynweigh/sim/scene.hpp"

namespace dynweigh::hal::linux_can {
namespace {

std::uint16_t base_port() { return std::uint16_t(20000 + (::getpid() % 20000)); }

std::string udp(std::uint16_t bind, std::uint16_t peer) {
  return "udp:" + std::to_string(bind) + "@127.0.0.1:" + std::to_string(peer);
}

TEST(CanTransportSpec, ParsesUdpAndRejectsMalformedSpecs) {
  const UdpSpec spec = parse_udp_spec("5001@127.0.0.1:5000");
  EXPECT_EQ(spec.bind_port, 5001);
  EXPECT_EQ(spec.peer_host, "127.0.0.1");
  EXPECT_EQ(spec.peer_port, 5000);
  EXPECT_THROW(parse_udp_spec("5001:5000"), std::invalid_argument);
  EXPECT_THROW(parse_udp_spec("x@127.0.0.1:5000"), std::invalid_argument);
  EXPECT_THROW(parse_udp_spec("5001@127.0.0.1:70000"), std::invalid_argument);
  EXPECT_THROW(parse_udp_spec("5001@:5000"), std::invalid_argument);
  EXPECT_THROW(open_can_transport("tcp:1"), std::invalid_argument);
  EXPECT_THROW(open_can_transport("socketcan:"), std::invalid_argument);
  EXPECT_THROW(open_can_transport("slcan:/nonexistent/device"), std::runtime_error);
}

TEST(UdpTransport, CarriesFramesBothWaysOnLoopback) {
  const std::uint16_t a = base_port(), b = std::uint16_t(a + 1);
  auto left = open_can_transport(udp(a, b));
  auto right = open_can_transport(udp(b, a));
  ASSERT_TRUE(left->send(can::encode(can::LoadCellSampleMessage{12345, 7, 0})));
  CanFrame frame;
  ASSERT_EQ(right->receive(frame, 2000), 1);
  can::LoadCellSampleMessage sample;
  ASSERT_TRUE(can::decode(frame, sample));
  EXPECT_EQ(sample.raw_counts, 12345);
  EXPECT_EQ(sample.counter, 7);
  ASSERT_TRUE(right->send(can::encode(can::ValveCommandMessage{2, 3, 7})));
  ASSERT_EQ(left->receive(frame, 2000), 1);
  EXPECT_EQ(frame.id, 0x220u);
  EXPECT_EQ(left->receive(frame, 10), 0);  // nothing more
}

TEST(UdpTransport, TwoBindsOnOnePortFail) {
  const std::uint16_t a = std::uint16_t(base_port() + 2);
  auto first = open_can_transport(udp(a, std::uint16_t(a + 1)));
  EXPECT_THROW(open_can_transport(udp(a, std::uint16_t(a + 1))), std::runtime_error);
}

class Pty {
 public:
  Pty() {
    master_ = ::posix_openpt(O_RDWR | O_NOCTTY);
    if (master_ < 0 || ::grantpt(master_) != 0 || ::unlockpt(master_) != 0) throw std::runtime_error("no pty");
    path_ = ::ptsname(master_);
  }
  ~Pty() { ::close(master_); }
  int master() const { return master_; }
  const std::string& path() const { return path_; }
  std::string read_some(int timeout_ms) const {
    pollfd p{master_, POLLIN, 0};
    if (::poll(&p, 1, timeout_ms) <= 0) return {};
    char buffer[256];
    const ssize_t n = ::read(master_, buffer, sizeof buffer);
    return n > 0 ? std::string(buffer, std::size_t(n)) : std::string();
  }

 private:
  int master_ = -1;
  std::string path_;
};

TEST(SlcanTransport, SpeaksLawicelOnAPty) {
  Pty pty;
  auto link = open_can_transport("slcan:" + pty.path());
  std::string seen;
  ASSERT_TRUE(link->send(can::encode(can::HeartbeatMessage{1, 5})));
  while (seen.find("t701105\r") == std::string::npos) {
    const std::string more = pty.read_some(2000);
    ASSERT_FALSE(more.empty()) << "got only: " << seen;
    seen += more;
  }
  EXPECT_EQ(seen.rfind("C\rS6\rO\r", 0), 0u);  // set-up for a real adapter comes first
  const std::string in = "z\rt1A020300\rt19";  // an ack, a frame, half a frame
  ASSERT_EQ(::write(pty.master(), in.data(), in.size()), ssize_t(in.size()));
  CanFrame frame;
  ASSERT_EQ(link->receive(frame, 2000), 1);
  EXPECT_EQ(frame.id, 0x1A0u);
  EXPECT_EQ(link->receive(frame, 50), 0);
  const std::string rest = "080100000000000000\r";
  ASSERT_EQ(::write(pty.master(), rest.data(), rest.size()), ssize_t(rest.size()));
  ASSERT_EQ(link->receive(frame, 2000), 1);
  can::LoadCellSampleMessage sample;
  ASSERT_TRUE(can::decode(frame, sample));
  EXPECT_EQ(sample.raw_counts, 1);
}

class NullConsole final : public ConsolePort {
 public:
  std::size_t read(char*, std::size_t) override { return 0; }
  void write(const char* data, std::size_t length) override { text.append(data, length); }
  std::string text;
};

TEST(CanBoard, AnswersEverySampleWithExactlyOneValveCommandCarryingItsCounter) {
  const std::uint16_t a = std::uint16_t(base_port() + 4), b = std::uint16_t(a + 1);
  auto board_link = open_can_transport(udp(a, b));
  auto plant_link = open_can_transport(udp(b, a));
  const sim::Plant reference(sim::default_scene(), 1);
  firmware::Indicator indicator(host::factory_settings(reference));
  NullConsole console;
  CanBoard board(*board_link, indicator, console);

  for (std::uint16_t k = 65530; k != 6; ++k) {  // across the counter's wrap
    ASSERT_TRUE(plant_link->send(can::encode(can::ValveFeedbackMessage{0, 0})));
    ASSERT_TRUE(plant_link->send(can::encode(can::LoadCellSampleMessage{12000, k, 0})));
    ASSERT_EQ(board.poll(2000), CanBoard::Event::jiffy);
    int commands = 0;
    CanFrame frame;
    while (plant_link->receive(frame, 20) == 1) {
      if (can::classify(frame) != can::MessageKind::valve_command) continue;
      can::ValveCommandMessage m;
      ASSERT_TRUE(can::decode(frame, m));
      EXPECT_EQ(m.counter, k);
      EXPECT_EQ(m.command, 0);
      ++commands;
    }
    EXPECT_EQ(commands, 1) << "sample " << k;
  }
  EXPECT_EQ(board.jiffy(), 12u);
}

TEST(CanBoard, MalformedAndForeignFramesRunNoJiffy) {
  const std::uint16_t a = std::uint16_t(base_port() + 6), b = std::uint16_t(a + 1);
  auto board_link = open_can_transport(udp(a, b));
  auto plant_link = open_can_transport(udp(b, a));
  const sim::Plant reference(sim::default_scene(), 1);
  firmware::Indicator indicator(host::factory_settings(reference));
  NullConsole console;
  CanBoard board(*board_link, indicator, console);
  CanFrame short_sample = can::encode(can::LoadCellSampleMessage{12000, 1, 0});
  short_sample.dlc = 6;
  ASSERT_TRUE(plant_link->send(short_sample));
  ASSERT_TRUE(plant_link->send(can::encode(can::HeartbeatMessage{0x10, 5})));
  CanFrame unknown;
  unknown.id = 0x555;
  ASSERT_TRUE(plant_link->send(unknown));
  EXPECT_EQ(board.poll(200), CanBoard::Event::quiet);
  EXPECT_EQ(board.jiffy(), 0u);
  EXPECT_EQ(board.frames_ignored(), 3u);
}

TEST(CanBoard, RealTimeRunsAJiffyWithoutASampleWhenTheLoadCellIsLate) {
  const std::uint16_t a = std::uint16_t(base_port() + 8), b = std::uint16_t(a + 1);
  auto board_link = open_can_transport(udp(a, b));
  const sim::Plant reference(sim::default_scene(), 1);
  firmware::Indicator indicator(host::factory_settings(reference));
  NullConsole console;
  CanBoard board(*board_link, indicator, console, nullptr, /*realtime=*/true);
  EXPECT_EQ(board.poll(1000), CanBoard::Event::stale_jiffy);
  EXPECT_EQ(board.jiffy(), 1u);
}

}  // namespace
}  // namespace dynweigh::hal::linux_can
