#include "dynweigh/hal/can/slcan.hpp"

namespace dynweigh::hal::can {
namespace {

constexpr char kHex[] = "0123456789ABCDEF";

int hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return -1;
}

bool parse_hex(const char* text, std::size_t digits, std::uint32_t& value) {
  std::uint32_t v = 0;
  for (std::size_t i = 0; i < digits; ++i) {
    const int h = hex_value(text[i]);
    if (h < 0) return false;
    v = (v << 4) | std::uint32_t(h);
  }
  value = v;
  return true;
}

}  // namespace

std::size_t slcan_encode(const CanFrame& frame, char* out, std::size_t capacity) {
  if (frame.dlc > 8) return 0;
  if (frame.extended ? frame.id > 0x1FFFFFFFu : frame.id > 0x7FFu) return 0;
  const std::size_t id_digits = frame.extended ? 8 : 3;
  const std::size_t data_digits = frame.remote ? 0 : 2u * frame.dlc;
  const std::size_t length = 1 + id_digits + 1 + data_digits + 1;
  if (capacity < length) return 0;
  std::size_t n = 0;
  out[n++] = frame.remote ? (frame.extended ? 'R' : 'r') : (frame.extended ? 'T' : 't');
  for (std::size_t i = id_digits; i-- > 0;) out[n++] = kHex[(frame.id >> (4 * i)) & 0xFu];
  out[n++] = char('0' + frame.dlc);
  for (std::size_t i = 0; i < data_digits / 2; ++i) {
    out[n++] = kHex[frame.data[i] >> 4];
    out[n++] = kHex[frame.data[i] & 0xFu];
  }
  out[n++] = '\r';
  return n;
}

bool SlcanDecoder::push(char c, CanFrame& frame) {
  if (c == '\r' || c == '\n' || c == '\a') {
    bool complete = false;
    if (overflow_) {
      ++errors_;
    } else if (length_ > 0) {
      const char kind = line_[0];
      if (kind == 't' || kind == 'T' || kind == 'r' || kind == 'R') {
        complete = parse(frame);
        if (!complete) ++errors_;
      }
      // Any other line is an adapter's answer or acknowledgement: not a frame, not an error.
    }
    length_ = 0;
    overflow_ = false;
    return complete;
  }
  if (length_ < kSlcanMaxLine) {
    line_[length_++] = c;
  } else {
    overflow_ = true;
  }
  return false;
}

bool SlcanDecoder::parse(CanFrame& frame) const {
  const char kind = line_[0];
  const bool extended = kind == 'T' || kind == 'R';
  const bool remote = kind == 'r' || kind == 'R';
  const std::size_t id_digits = extended ? 8 : 3;
  if (length_ < 1 + id_digits + 1) return false;
  std::uint32_t id = 0;
  if (!parse_hex(line_ + 1, id_digits, id)) return false;
  if (extended ? id > 0x1FFFFFFFu : id > 0x7FFu) return false;
  const int dlc = line_[1 + id_digits] - '0';
  if (dlc < 0 || dlc > 8) return false;
  const std::size_t expected = 1 + id_digits + 1 + (remote ? 0 : 2 * std::size_t(dlc));
  if (length_ != expected) return false;
  CanFrame f;
  f.id = id;
  f.extended = extended;
  f.remote = remote;
  f.dlc = std::uint8_t(dlc);
  for (int i = 0; !remote && i < dlc; ++i) {
    std::uint32_t byte = 0;
    if (!parse_hex(line_ + 1 + id_digits + 1 + 2 * std::size_t(i), 2, byte)) return false;
    f.data[i] = std::uint8_t(byte);
  }
  frame = f;
  return true;
}

}  // namespace dynweigh::hal::can
