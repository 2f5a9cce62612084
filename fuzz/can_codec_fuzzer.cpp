// Fuzz target: arbitrary bytes as Linux `struct can_frame` images (docs/can-protocol.md, the udp transport), 16
// bytes a frame, and each accepted frame through every message decoder of docs/can-protocol.md.
//
// Invariants: an accepted frame has a DLC of at most 8 and an identifier in range, and converts
// back to the same bytes; a short image is refused; at most one decoder accepts a frame, and only
// the one its identifier names; a decoded message encodes to a frame that decodes to the same
// message. The decoders are also fed frames built field by field from the input (any DLC), the
// way a faulty board might hand them over.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "dynweigh/hal/can/can_frame.hpp"
#include "dynweigh/hal/can/protocol.hpp"

namespace {

using namespace dynweigh::hal::can;

[[noreturn]] void violated(const char* what) {
  std::fprintf(stderr, "CAN codec invariant violated: %s\n", what);
  std::abort();
}

bool same(const LoadCellSampleMessage& a, const LoadCellSampleMessage& b) {
  return a.raw_counts == b.raw_counts && a.counter == b.counter && a.status == b.status;
}
bool same(const ValveCommandMessage& a, const ValveCommandMessage& b) {
  return a.command == b.command && a.delay_100us == b.delay_100us && a.counter == b.counter;
}
bool same(const ValveFeedbackMessage& a, const ValveFeedbackMessage& b) {
  return a.position == b.position && a.faults == b.faults;
}
bool same(const IndicatorStatusMessage& a, const IndicatorStatusMessage& b) {
  return a.weight_100mg == b.weight_100mg && a.state == b.state && a.valve == b.valve && a.counter == b.counter;
}
bool same(const HeartbeatMessage& a, const HeartbeatMessage& b) {
  return a.node == b.node && a.nmt_state == b.nmt_state;
}
bool same(const GateCommandMessage& a, const GateCommandMessage& b) {
  return a.command == b.command && a.counter == b.counter;
}
bool same(const GateFeedbackMessage& a, const GateFeedbackMessage& b) {
  return a.position == b.position && a.faults == b.faults;
}

// Decodes `frame` as `Message`; if accepted, checks the identifier and the round trip. Returns
// whether it was accepted.
template <typename Message>
bool try_decoder(const CanFrame& frame, MessageKind kind) {
  Message message;
  if (!decode(frame, message)) return false;
  if (classify(frame) != kind) violated("a decoder accepted a frame of another identifier");
  if (frame.extended || frame.remote || frame.dlc > 8) violated("a decoder accepted a malformed frame");
  const CanFrame again = encode(message);
  if (classify(again) != kind) violated("an encoded message has another identifier");
  Message round;
  if (!decode(again, round) || !same(message, round)) violated("encode/decode does not round-trip");
  return true;
}

void check_decoders(const CanFrame& frame) {
  const int accepted = int(try_decoder<LoadCellSampleMessage>(frame, MessageKind::load_cell_sample)) +
                       int(try_decoder<ValveCommandMessage>(frame, MessageKind::valve_command)) +
                       int(try_decoder<ValveFeedbackMessage>(frame, MessageKind::valve_feedback)) +
                       int(try_decoder<IndicatorStatusMessage>(frame, MessageKind::indicator_status)) +
                       int(try_decoder<HeartbeatMessage>(frame, MessageKind::heartbeat)) +
                       int(try_decoder<GateCommandMessage>(frame, MessageKind::gate_command)) +
                       int(try_decoder<GateFeedbackMessage>(frame, MessageKind::gate_feedback));
  if (accepted > 1) violated("more than one decoder accepted a frame");
  if (message_name(classify(frame)) == nullptr) violated("a message kind without a name");
}

void check_linux_image(const std::uint8_t* bytes, unsigned length) {
  CanFrame frame;
  if (!from_linux_bytes(bytes, length, frame)) return;
  if (length != kLinuxFrameSize) violated("a short or long image was accepted");
  if (frame.dlc > 8) violated("an accepted frame has a DLC over 8");
  if (frame.id > (frame.extended ? 0x1FFFFFFFu : 0x7FFu)) violated("an accepted frame has an identifier out of range");
  std::uint8_t again[kLinuxFrameSize];
  to_linux_bytes(frame, again);
  if (std::memcmp(again, bytes, 5) != 0 || std::memcmp(again + 8, bytes + 8, frame.dlc) != 0) {
    violated("a frame does not convert back to its bytes");
  }
  CanFrame round;
  if (!from_linux_bytes(again, kLinuxFrameSize, round) || !(round == frame)) violated("linux bytes do not round-trip");
  check_decoders(frame);
}

// A frame as a careless driver could fill it in: every field straight from the input.
void check_raw_fields(const std::uint8_t* bytes) {
  CanFrame frame;
  std::memcpy(&frame.id, bytes, 4);
  frame.extended = (bytes[4] & 1) != 0;
  frame.remote = (bytes[4] & 2) != 0;
  frame.dlc = bytes[5];
  std::memcpy(frame.data, bytes + 6, 8);
  check_decoders(frame);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::size_t offset = 0;
  for (; offset + kLinuxFrameSize <= size; offset += kLinuxFrameSize) {
    check_linux_image(data + offset, kLinuxFrameSize);
    check_raw_fields(data + offset);
  }
  if (offset < size) {  // the tail: a datagram cut short
    std::uint8_t tail[kLinuxFrameSize] = {};
    std::memcpy(tail, data + offset, size - offset);
    check_linux_image(tail, unsigned(size - offset));
  }
  return 0;
}
