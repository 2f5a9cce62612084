// The CAN frames' values are one declaration each (schema/can_values.hpp): the firmware's and the
// simulator's names are the same types, so a value passes between them without a cast, and each
// has the number docs/can-protocol.md gives it on the wire.
#include <gtest/gtest.h>

#include <type_traits>

#include "dynweigh/firmware/io.hpp"
#include "dynweigh/schema/can_values.hpp"
#include "dynweigh/sim/load_cell.hpp"
#include "dynweigh/sim/valve_command.hpp"

namespace dynweigh::testing {
namespace {

TEST(CanValues, TheFirmwareAndTheSimulatorShareOneTypeForEachValue) {
  EXPECT_TRUE((std::is_same_v<firmware::ValveCommand, sim::ValveCommand>));
  EXPECT_TRUE((std::is_same_v<firmware::ValvePosition, sim::ValvePosition>));
  EXPECT_TRUE((std::is_same_v<firmware::ValveCommand, schema::ValveCommand>));
  EXPECT_TRUE((std::is_same_v<firmware::IndicatorState, schema::IndicatorState>));
  EXPECT_EQ(&firmware::kLoadCellOverload, &schema::kLoadCellOverload);
}

TEST(CanValues, EachValueIsTheNumberOnTheWire) {
  EXPECT_EQ(int(schema::ValveCommand::closed), 0);
  EXPECT_EQ(int(schema::ValveCommand::half), 1);
  EXPECT_EQ(int(schema::ValveCommand::open), 2);
  EXPECT_EQ(int(schema::ValvePosition::closed), 0);
  EXPECT_EQ(int(schema::ValvePosition::moving), 1);
  EXPECT_EQ(int(schema::ValvePosition::half), 2);
  EXPECT_EQ(int(schema::ValvePosition::open), 3);
  EXPECT_EQ(schema::kLoadCellOverload, 0x01);
  EXPECT_EQ(schema::kLoadCellUnderload, 0x02);
  EXPECT_EQ(schema::kLoadCellAdcError, 0x04);
  EXPECT_EQ(int(schema::IndicatorState::idle), 0);
  EXPECT_EQ(int(schema::IndicatorState::dosing), 1);
  EXPECT_EQ(int(schema::IndicatorState::settling), 2);
  EXPECT_EQ(int(schema::IndicatorState::fault), 3);
}

}  // namespace
}  // namespace dynweigh::testing
