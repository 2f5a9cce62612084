// Fuzz target: arbitrary bytes from an SLCAN (Lawicel) serial adapter into the line decoder, and
// each frame it completes through the CAN protocol's decoders (docs/can-protocol.md).
//
// Invariants: a completed frame has a DLC of at most 8 and an identifier in range; it encodes
// back to exactly the line that carried it (hex digits compared without case); the error count
// never exceeds the number of lines and never decreases.
#include <cctype>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "dynweigh/hal/can/protocol.hpp"
#include "dynweigh/hal/can/slcan.hpp"

namespace {

using namespace dynweigh::hal::can;

[[noreturn]] void violated(const char* what) {
  std::fprintf(stderr, "SLCAN invariant violated: %s\n", what);
  std::abort();
}

bool terminator(char c) { return c == '\r' || c == '\n' || c == '\a'; }

// The line the decoder saw, as far as a frame line can be long.
struct LineCopy {
  char text[kSlcanMaxLine + 2] = {};
  std::size_t length = 0;
  bool overlong = false;
  void push(char c) {
    if (length < sizeof text) {
      text[length++] = c;
    } else {
      overlong = true;
    }
  }
  void clear() {
    length = 0;
    overlong = false;
  }
};

void check_frame(const CanFrame& frame, const LineCopy& line) {
  if (frame.dlc > 8) violated("a frame with a DLC over 8");
  if (frame.id > (frame.extended ? 0x1FFFFFFFu : 0x7FFu)) violated("a frame with an identifier out of range");
  if (line.overlong) violated("a frame from a line longer than any frame line");
  char encoded[kSlcanMaxLine + 1];
  const std::size_t n = slcan_encode(frame, encoded, sizeof encoded);
  if (n == 0) violated("a decoded frame cannot be encoded");
  if (n - 1 != line.length) violated("a frame from a line of another length than its encoding");
  if (line.text[0] != encoded[0]) violated("a frame of another kind than its line");
  for (std::size_t i = 1; i < line.length; ++i) {  // hex digits in either case
    if (std::toupper(static_cast<unsigned char>(line.text[i])) != encoded[i]) violated("a frame from another line");
  }
  SlcanDecoder fresh;
  CanFrame round;
  bool completed = false;
  for (std::size_t i = 0; i < n; ++i) completed = fresh.push(encoded[i], round);
  if (!completed || !(round == frame)) violated("encode/decode does not round-trip");
  // The frame goes on into the protocol decoders, which must refuse or accept it cleanly.
  LoadCellSampleMessage sample;
  ValveCommandMessage command;
  ValveFeedbackMessage feedback;
  IndicatorStatusMessage status;
  HeartbeatMessage heartbeat;
  const int accepted = int(decode(frame, sample)) + int(decode(frame, command)) + int(decode(frame, feedback)) +
                       int(decode(frame, status)) + int(decode(frame, heartbeat));
  if (accepted > 1) violated("more than one protocol decoder accepted a frame");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  SlcanDecoder decoder;
  LineCopy line;
  std::uint32_t lines = 0, errors = 0;
  for (std::size_t i = 0; i < size; ++i) {
    const char c = char(data[i]);
    CanFrame frame;
    const bool completed = decoder.push(c, frame);
    if (completed && !terminator(c)) violated("a frame completed without a line end");
    if (terminator(c)) {
      ++lines;
      if (completed) check_frame(frame, line);
      line.clear();
    } else {
      line.push(c);
    }
    if (decoder.errors() < errors || decoder.errors() > lines) violated("the error count went wrong");
    errors = decoder.errors();
  }
  return 0;
}
