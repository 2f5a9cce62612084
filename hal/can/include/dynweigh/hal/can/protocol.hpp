#pragma once
// The plant link (docs/can-protocol.md): CANopen COB-IDs (CiA 301), little-endian payloads, one sample per
// jiffy. One encode/decode pair per message; a decoder returns false (and leaves its output alone)
// for a frame with another identifier, the wrong DLC, an extended or remote frame, or a value out
// of range.
#include <cstdint>

#include "dynweigh/hal/can/can_frame.hpp"

namespace dynweigh::hal::can {

inline constexpr std::uint8_t kNodeIndicator = 0x01;
inline constexpr std::uint8_t kNodeLoadCell = 0x10;
inline constexpr std::uint8_t kNodeValve = 0x20;
inline constexpr std::uint8_t kNodeGate = 0x28;  // the discharge gate under the hopper

inline constexpr std::uint32_t kIdLoadCellSample = 0x180 + kNodeLoadCell;  // 0x190 TPDO1
inline constexpr std::uint32_t kIdValveCommand = 0x200 + kNodeValve;       // 0x220 RPDO1
inline constexpr std::uint32_t kIdValveFeedback = 0x180 + kNodeValve;      // 0x1A0 TPDO1
inline constexpr std::uint32_t kIdIndicatorStatus = 0x180 + kNodeIndicator;  // 0x181 TPDO1
inline constexpr std::uint32_t kIdHeartbeatBase = 0x700;                   // + node
inline constexpr std::uint32_t kIdGateCommand = 0x200 + kNodeGate;         // 0x228 RPDO1
inline constexpr std::uint32_t kIdGateFeedback = 0x180 + kNodeGate;        // 0x1A8 TPDO1

// CiA 301 NMT states as heartbeats carry them.
inline constexpr std::uint8_t kNmtBootUp = 0x00;
inline constexpr std::uint8_t kNmtStopped = 0x04;
inline constexpr std::uint8_t kNmtOperational = 0x05;
inline constexpr std::uint8_t kNmtPreOperational = 0x7F;

inline constexpr std::uint8_t kMaxValveDelay100us = 99;

struct LoadCellSampleMessage {   // 0x190, DLC 8
  std::int32_t raw_counts = 0;
  std::uint16_t counter = 0;
  std::uint8_t status = 0;       // bit0 overload, bit1 underload, bit2 ADC error
};

struct ValveCommandMessage {     // 0x220, DLC 4
  std::uint8_t command = 0;      // 0 closed, 1 half, 2 open
  std::uint8_t delay_100us = 0;  // 0..99
  std::uint16_t counter = 0;     // of the sample it answers
};

struct ValveFeedbackMessage {    // 0x1A0, DLC 2
  std::uint8_t position = 0;     // 0 closed, 1 moving, 2 half, 3 open
  std::uint8_t faults = 0;
};

struct IndicatorStatusMessage {  // 0x181, DLC 8
  std::int32_t weight_100mg = 0;
  std::uint8_t state = 0;        // 0 idle, 1 dosing, 2 settling, 3 fault
  std::uint8_t valve = 0;
  std::uint16_t counter = 0;
};

struct HeartbeatMessage {        // 0x700 + node, DLC 1
  std::uint8_t node = 0;         // 1..127
  std::uint8_t nmt_state = kNmtOperational;
};

struct GateCommandMessage {      // 0x228, DLC 4
  std::uint8_t command = 0;      // 0 closed, 2 open
  std::uint16_t counter = 0;     // of the sample it answers
};

struct GateFeedbackMessage {     // 0x1A8, DLC 2
  std::uint8_t position = 0;     // 0 closed, 1 moving, 3 open
  std::uint8_t faults = 0;
};

enum class MessageKind : std::uint8_t {
  unknown,
  load_cell_sample,
  valve_command,
  valve_feedback,
  indicator_status,
  heartbeat,
  gate_command,
  gate_feedback,
};

// By identifier only: says which decoder to try, not that the frame is well-formed.
MessageKind classify(const CanFrame& frame);
const char* message_name(MessageKind kind);

CanFrame encode(const LoadCellSampleMessage& message);
CanFrame encode(const ValveCommandMessage& message);
CanFrame encode(const ValveFeedbackMessage& message);
CanFrame encode(const IndicatorStatusMessage& message);
CanFrame encode(const HeartbeatMessage& message);
CanFrame encode(const GateCommandMessage& message);
CanFrame encode(const GateFeedbackMessage& message);

bool decode(const CanFrame& frame, LoadCellSampleMessage& message);
bool decode(const CanFrame& frame, ValveCommandMessage& message);
bool decode(const CanFrame& frame, ValveFeedbackMessage& message);
bool decode(const CanFrame& frame, IndicatorStatusMessage& message);
bool decode(const CanFrame& frame, HeartbeatMessage& message);
bool decode(const CanFrame& frame, GateCommandMessage& message);
bool decode(const CanFrame& frame, GateFeedbackMessage& message);

}  // namespace dynweigh::hal::can
