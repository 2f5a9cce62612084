#pragma once
// The values of the plant link's frames (docs/can-protocol.md), one declaration each. The numbers
// are the bytes on the wire: a board encodes a value with std::uint8_t(value) and nothing else.
#include <cstdint>

namespace dynweigh::schema {

// 0x220 byte 0: what the indicator asks of the valve module.
enum class ValveCommand : std::uint8_t { closed = 0, half = 1, open = 2 };

// 0x1A0 byte 0: where the valve module says the valve is.
enum class ValvePosition : std::uint8_t { closed = 0, moving = 1, half = 2, open = 3 };

// 0x228 byte 0: what the indicator asks of the discharge gate module (no half position).
enum class GateCommand : std::uint8_t { closed = 0, open = 2 };

// 0x1A8 byte 0: where the discharge gate module says the gate is.
enum class GatePosition : std::uint8_t { closed = 0, moving = 1, open = 3 };

// 0x190 byte 6: the load cell's converter status bits.
inline constexpr std::uint8_t kLoadCellOverload = 0x01;
inline constexpr std::uint8_t kLoadCellUnderload = 0x02;
inline constexpr std::uint8_t kLoadCellAdcError = 0x04;

// 0x181 byte 4: the indicator's state.
enum class IndicatorState : std::uint8_t { idle = 0, dosing = 1, settling = 2, fault = 3 };

}  // namespace dynweigh::schema
