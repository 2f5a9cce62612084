#include "dynweigh/hal/can/protocol.hpp"

namespace dynweigh::hal::can {
namespace {

void put_u16(std::uint8_t* p, std::uint16_t v) {
  p[0] = std::uint8_t(v & 0xFFu);
  p[1] = std::uint8_t(v >> 8);
}
void put_u32(std::uint8_t* p, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = std::uint8_t((v >> (8 * i)) & 0xFFu);
}
std::uint16_t get_u16(const std::uint8_t* p) { return std::uint16_t(p[0] | (p[1] << 8)); }
std::uint32_t get_u32(const std::uint8_t* p) {
  return std::uint32_t(p[0]) | (std::uint32_t(p[1]) << 8) | (std::uint32_t(p[2]) << 16) | (std::uint32_t(p[3]) << 24);
}

CanFrame frame_of(std::uint32_t id, std::uint8_t dlc) {
  CanFrame f;
  f.id = id;
  f.dlc = dlc;
  return f;
}

// A data frame with this standard identifier and exactly this DLC.
bool shaped(const CanFrame& f, std::uint32_t id, std::uint8_t dlc) {
  return f.id == id && !f.extended && !f.remote && f.dlc == dlc;
}

}  // namespace

void to_linux_bytes(const CanFrame& frame, std::uint8_t (&out)[kLinuxFrameSize]) {
  std::uint32_t id = frame.id & (frame.extended ? 0x1FFFFFFFu : 0x7FFu);
  if (frame.extended) id |= kLinuxEffFlag;
  if (frame.remote) id |= kLinuxRtrFlag;
  put_u32(out, id);
  out[4] = frame.dlc > 8 ? 8 : frame.dlc;
  out[5] = out[6] = out[7] = 0;
  for (int i = 0; i < 8; ++i) out[8 + i] = i < out[4] ? frame.data[i] : 0;
}

bool from_linux_bytes(const std::uint8_t* bytes, unsigned length, CanFrame& frame) {
  if (length != kLinuxFrameSize) return false;
  const std::uint32_t raw = get_u32(bytes);
  if (raw & kLinuxErrFlag) return false;
  if (bytes[4] > 8) return false;
  CanFrame f;
  f.extended = (raw & kLinuxEffFlag) != 0;
  f.remote = (raw & kLinuxRtrFlag) != 0;
  f.id = raw & 0x1FFFFFFFu;
  if (!f.extended && f.id > 0x7FFu) return false;
  f.dlc = bytes[4];
  for (int i = 0; i < f.dlc; ++i) f.data[i] = bytes[8 + i];
  frame = f;
  return true;
}

MessageKind classify(const CanFrame& frame) {
  if (frame.extended) return MessageKind::unknown;
  switch (frame.id) {
    case kIdLoadCellSample: return MessageKind::load_cell_sample;
    case kIdValveCommand: return MessageKind::valve_command;
    case kIdValveFeedback: return MessageKind::valve_feedback;
    case kIdIndicatorStatus: return MessageKind::indicator_status;
    case kIdGateCommand: return MessageKind::gate_command;
    case kIdGateFeedback: return MessageKind::gate_feedback;
    default: break;
  }
  if (frame.id > kIdHeartbeatBase && frame.id < kIdHeartbeatBase + 0x80) return MessageKind::heartbeat;
  return MessageKind::unknown;
}

const char* message_name(MessageKind kind) {
  switch (kind) {
    case MessageKind::load_cell_sample: return "load_cell_sample";
    case MessageKind::valve_command: return "valve_command";
    case MessageKind::valve_feedback: return "valve_feedback";
    case MessageKind::indicator_status: return "indicator_status";
    case MessageKind::heartbeat: return "heartbeat";
    case MessageKind::gate_command: return "gate_command";
    case MessageKind::gate_feedback: return "gate_feedback";
    case MessageKind::unknown: break;
  }
  return "unknown";
}

CanFrame encode(const LoadCellSampleMessage& m) {
  CanFrame f = frame_of(kIdLoadCellSample, 8);
  put_u32(f.data, std::uint32_t(m.raw_counts));
  put_u16(f.data + 4, m.counter);
  f.data[6] = m.status;
  f.data[7] = 0;
  return f;
}

CanFrame encode(const ValveCommandMessage& m) {
  CanFrame f = frame_of(kIdValveCommand, 4);
  f.data[0] = m.command;
  f.data[1] = m.delay_100us > kMaxValveDelay100us ? kMaxValveDelay100us : m.delay_100us;
  put_u16(f.data + 2, m.counter);
  return f;
}

CanFrame encode(const ValveFeedbackMessage& m) {
  CanFrame f = frame_of(kIdValveFeedback, 2);
  f.data[0] = m.position;
  f.data[1] = m.faults;
  return f;
}

CanFrame encode(const IndicatorStatusMessage& m) {
  CanFrame f = frame_of(kIdIndicatorStatus, 8);
  put_u32(f.data, std::uint32_t(m.weight_100mg));
  f.data[4] = m.state;
  f.data[5] = m.valve;
  put_u16(f.data + 6, m.counter);
  return f;
}

CanFrame encode(const HeartbeatMessage& m) {
  CanFrame f = frame_of(kIdHeartbeatBase + (m.node & 0x7Fu), 1);
  f.data[0] = m.nmt_state;
  return f;
}

bool decode(const CanFrame& f, LoadCellSampleMessage& m) {
  if (!shaped(f, kIdLoadCellSample, 8)) return false;
  m.raw_counts = std::int32_t(get_u32(f.data));
  m.counter = get_u16(f.data + 4);
  m.status = f.data[6];
  return true;
}

bool decode(const CanFrame& f, ValveCommandMessage& m) {
  if (!shaped(f, kIdValveCommand, 4)) return false;
  if (f.data[0] > 2 || f.data[1] > kMaxValveDelay100us) return false;
  m.command = f.data[0];
  m.delay_100us = f.data[1];
  m.counter = get_u16(f.data + 2);
  return true;
}

bool decode(const CanFrame& f, ValveFeedbackMessage& m) {
  if (!shaped(f, kIdValveFeedback, 2)) return false;
  if (f.data[0] > 3) return false;
  m.position = f.data[0];
  m.faults = f.data[1];
  return true;
}

bool decode(const CanFrame& f, IndicatorStatusMessage& m) {
  if (!shaped(f, kIdIndicatorStatus, 8)) return false;
  if (f.data[4] > 3 || f.data[5] > 2) return false;
  m.weight_100mg = std::int32_t(get_u32(f.data));
  m.state = f.data[4];
  m.valve = f.data[5];
  m.counter = get_u16(f.data + 6);
  return true;
}

bool decode(const CanFrame& f, HeartbeatMessage& m) {
  if (classify(f) != MessageKind::heartbeat || f.remote || f.dlc != 1) return false;
  m.node = std::uint8_t(f.id - kIdHeartbeatBase);
  m.nmt_state = f.data[0];
  return true;
}

CanFrame encode(const GateCommandMessage& m) {
  CanFrame f = frame_of(kIdGateCommand, 4);
  f.data[0] = m.command;
  f.data[1] = 0;
  put_u16(f.data + 2, m.counter);
  return f;
}

CanFrame encode(const GateFeedbackMessage& m) {
  CanFrame f = frame_of(kIdGateFeedback, 2);
  f.data[0] = m.position;
  f.data[1] = m.faults;
  return f;
}

// The gate has no half position: a command 1 is as wrong as 3.
bool decode(const CanFrame& f, GateCommandMessage& m) {
  if (!shaped(f, kIdGateCommand, 4)) return false;
  if (f.data[0] != 0 && f.data[0] != 2) return false;
  m.command = f.data[0];
  m.counter = get_u16(f.data + 2);
  return true;
}

bool decode(const CanFrame& f, GateFeedbackMessage& m) {
  if (!shaped(f, kIdGateFeedback, 2)) return false;
  if (f.data[0] != 0 && f.data[0] != 1 && f.data[0] != 3) return false;
  m.position = f.data[0];
  m.faults = f.data[1];
  return true;
}

}  // namespace dynweigh::hal::can
