// The PLC interface without sockets: the register map's decoding (exceptions, the 32-bit set
// point, commands as console lines), the RESULT fields, the --modbus syntax, and the PLC's commands
// on the console's command path against the indicator and the in-process plant.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "dynweigh/hal/host/lockstep_session.hpp"
#include "dynweigh/modbus/endpoint.hpp"
#include "dynweigh/modbus/plc_console.hpp"
#include "dynweigh/modbus/plc_mailbox.hpp"
#include "dynweigh/modbus/register_map.hpp"
#include "dynweigh/modbus/result_fields.hpp"
#include "dynweigh/sim/scene.hpp"

namespace {

using namespace dynweigh;
using modbus::Exception;
using modbus::LoopSnapshot;
using modbus::RegisterMap;

std::vector<std::uint8_t> pdu(std::uint8_t function, std::vector<std::uint16_t> words) {
  std::vector<std::uint8_t> bytes{function};
  for (std::uint16_t w : words) {
    bytes.push_back(std::uint8_t(w >> 8));
    bytes.push_back(std::uint8_t(w));
  }
  return bytes;
}

std::vector<std::uint8_t> write_multiple(std::uint16_t address, std::vector<std::uint16_t> values) {
  std::vector<std::uint8_t> bytes = pdu(modbus::kWriteMultipleRegisters, {address, std::uint16_t(values.size())});
  bytes.push_back(std::uint8_t(2 * values.size()));
  for (std::uint16_t v : values) {
    bytes.push_back(std::uint8_t(v >> 8));
    bytes.push_back(std::uint8_t(v));
  }
  return bytes;
}

struct Map {
  RegisterMap map;
  LoopSnapshot loop;
  std::uint16_t registers[125] = {};
  std::size_t count = 0;
  RegisterMap::Outcome send(const std::vector<std::uint8_t>& request) {
    return map.handle(request.data(), request.size(), loop, registers, &count);
  }
  std::vector<std::uint16_t> holding() {
    EXPECT_EQ(send(pdu(modbus::kReadHoldingRegisters, {0, 6})).exception, Exception::none);
    return std::vector<std::uint16_t>(registers, registers + count);
  }
};

TEST(ModbusRegisterMap, AnswersExceptionsForUnknownFunctionsAddressesAndValues) {
  Map m;
  EXPECT_EQ(m.send({0x41}).exception, Exception::illegal_function);
  EXPECT_EQ(m.send({}).exception, Exception::illegal_function);
  EXPECT_EQ(m.send(pdu(0x01, {0, 1})).exception, Exception::illegal_function);
  EXPECT_EQ(m.send(pdu(modbus::kReadInputRegisters, {17, 2})).exception, Exception::illegal_data_address);
  EXPECT_EQ(m.send(pdu(modbus::kReadInputRegisters, {0xFFFF, 2})).exception, Exception::illegal_data_address);
  EXPECT_EQ(m.send(pdu(modbus::kReadHoldingRegisters, {6, 1})).exception, Exception::illegal_data_address);
  EXPECT_EQ(m.send(pdu(modbus::kWriteSingleRegister, {6, 0})).exception, Exception::illegal_data_address);
  EXPECT_EQ(m.send(pdu(modbus::kReadInputRegisters, {0, 0})).exception, Exception::illegal_data_value);
  EXPECT_EQ(m.send(pdu(modbus::kReadInputRegisters, {0, 126})).exception, Exception::illegal_data_value);
  EXPECT_EQ(m.send({modbus::kReadInputRegisters, 0, 0, 0}).exception, Exception::illegal_data_value);
  EXPECT_EQ(m.send(pdu(modbus::kWriteSingleRegister, {2, 4})).exception, Exception::illegal_data_value);
  EXPECT_EQ(m.send(pdu(modbus::kWriteSingleRegister, {3, 16})).exception, Exception::illegal_data_value);
  EXPECT_EQ(m.send(pdu(modbus::kWriteSingleRegister, {4, 5})).exception, Exception::illegal_data_value);
  EXPECT_EQ(m.send(pdu(modbus::kWriteSingleRegister, {5, 0})).exception, Exception::illegal_data_value);
  EXPECT_EQ(m.send(pdu(modbus::kWriteSingleRegister, {5, 9})).exception, Exception::illegal_data_value);
  std::vector<std::uint8_t> short_count = write_multiple(0, {1, 2});
  short_count[5] = 2;  // byte count says one register, two follow
  EXPECT_EQ(m.send(short_count).exception, Exception::illegal_data_value);
  EXPECT_EQ(m.send(pdu(modbus::kWriteSingleRegister, {4, 10})).exception, Exception::none);
  EXPECT_EQ(m.send(pdu(modbus::kReadInputRegisters, {0, 18})).exception, Exception::none);
  EXPECT_EQ(m.count, 18u);
}

TEST(ModbusRegisterMap, ARefusedWriteChangesNothing) {
  Map m;
  EXPECT_EQ(m.send(write_multiple(0, {0, 700, 1, 0, 0, 1})).exception, Exception::none);
  const std::vector<std::uint16_t> before = m.holding();
  EXPECT_EQ(m.send(write_multiple(0, {0, 900, 9})).exception, Exception::illegal_data_value);
  EXPECT_EQ(m.send(write_multiple(3, {0, 0, 0, 0})).exception, Exception::illegal_data_address);
  EXPECT_EQ(m.holding(), before);
}

TEST(ModbusRegisterMap, ASplitSetPointTakesEffectWithItsLowWord) {
  Map m;
  EXPECT_EQ(m.send(pdu(modbus::kWriteSingleRegister, {0, 0x0001})).exception, Exception::none);
  EXPECT_EQ(m.map.target_g(), 0u);
  EXPECT_EQ(m.holding()[0], 0u);
  EXPECT_EQ(m.send(pdu(modbus::kWriteSingleRegister, {1, 0x86A0})).exception, Exception::none);
  EXPECT_EQ(m.map.target_g(), 100000u);
  // A low word alone keeps the high word written last.
  EXPECT_EQ(m.send(pdu(modbus::kWriteSingleRegister, {1, 0x0002})).exception, Exception::none);
  EXPECT_EQ(m.map.target_g(), 0x10002u);
  // Both in one 0x10 request: at once.
  EXPECT_EQ(m.send(write_multiple(0, {0, 5000})).exception, Exception::none);
  EXPECT_EQ(m.map.target_g(), 5000u);
  const std::vector<std::uint16_t> h = m.holding();
  EXPECT_EQ(h[0], 0u);
  EXPECT_EQ(h[1], 5000u);
}

TEST(ModbusRegisterMap, ACommandIsItsConsoleLineAndRunsUntilTheLoopAnswersIt) {
  Map m;
  const RegisterMap::Outcome dose = m.send(write_multiple(0, {0, 5000, 2, 0, 0, 1}));
  ASSERT_TRUE(dose.command_written);
  EXPECT_STREQ(dose.command.line, "dose 5000 twostage");
  EXPECT_EQ(m.holding()[5], modbus::kCommandRunning);
  // Another command while it runs: busy; an abort goes through.
  EXPECT_EQ(m.send(pdu(modbus::kWriteSingleRegister, {5, 3})).exception, Exception::server_busy);
  const RegisterMap::Outcome abort = m.send(pdu(modbus::kWriteSingleRegister, {5, 2}));
  ASSERT_TRUE(abort.command_written);
  EXPECT_STREQ(abort.command.line, "abort");
  m.loop.answered_sequence = abort.command.sequence;
  m.loop.answer_code = 3;
  EXPECT_EQ(m.holding()[5], 3u);
  const char* words[] = {"", "", "", "tare", "zero", "clearfault", "discharge", "accept", "topup"};
  for (std::uint16_t command = 3; command <= 8; ++command) {
    const RegisterMap::Outcome o = m.send(pdu(modbus::kWriteSingleRegister, {5, command}));
    ASSERT_TRUE(o.command_written);
    EXPECT_STREQ(o.command.line, words[command]);
    m.loop.answered_sequence = o.command.sequence;
  }
}

TEST(ModbusRegisterMap, AWrittenMaterialIsSelectedOnTheLineBeforeTheNextDose) {
  Map m;
  m.loop.selected_material = 2;  // the console selected it
  EXPECT_EQ(m.holding()[3], 2u);
  ASSERT_EQ(m.send(pdu(modbus::kWriteSingleRegister, {3, 15})).exception, Exception::none);
  EXPECT_EQ(m.holding()[3], 15u);
  const RegisterMap::Outcome dose = m.send(write_multiple(0, {0, 800, 1}));
  EXPECT_EQ(dose.command_written, false);
  const RegisterMap::Outcome start = m.send(pdu(modbus::kWriteSingleRegister, {5, 1}));
  ASSERT_TRUE(start.command_written);
  EXPECT_STREQ(start.command.line, "material 15\ndose 800 preact");
  m.loop.answered_sequence = start.command.sequence;
  m.loop.selected_material = 15;
  // The next dose selects nothing; a written material already selected neither.
  const RegisterMap::Outcome again = m.send(pdu(modbus::kWriteSingleRegister, {5, 1}));
  EXPECT_STREQ(again.command.line, "dose 800 preact");
  m.loop.answered_sequence = again.command.sequence;
  const RegisterMap::Outcome same = m.send(write_multiple(3, {15, 0, 1}));
  EXPECT_STREQ(same.command.line, "dose 800 preact");
}

TEST(ModbusResultFields, ReadsTheRegistersFieldsByKeyAndMissingOnesAsZero) {
  modbus::ResultFields f;
  EXPECT_FALSE(modbus::parse_result_line("STATUS state=idle", f));
  ASSERT_TRUE(modbus::parse_result_line("RESULT target=5000 final=4981 error=-19 time=3350 cutoff=258 strategy=model", f));
  EXPECT_EQ(f.final_g, 4981);
  EXPECT_EQ(f.error_g, -19);
  EXPECT_EQ(f.time_ms, 3350u);
  EXPECT_EQ(f.tolerance, 0u);
  EXPECT_EQ(f.topups, 0u);
  ASSERT_TRUE(modbus::parse_result_line(
      "RESULT target=500 final=470 error=-30 time=900 cutoff=50 strategy=model tolerance=low topups=2", f));
  EXPECT_EQ(f.tolerance, 3u);
  EXPECT_EQ(f.topups, 2u);
}

TEST(ModbusEndpoint, ParsesTcpAndRtuAndRefusesTheRest) {
  std::string error;
  const auto tcp = modbus::parse_endpoint("tcp:127.0.0.1:1502", error);
  ASSERT_TRUE(tcp);
  EXPECT_EQ(tcp->host, "127.0.0.1");
  EXPECT_EQ(tcp->port, "1502");
  const auto rtu = modbus::parse_endpoint("rtu:/dev/ttyUSB0:19200:8E1:7", error);
  ASSERT_TRUE(rtu);
  EXPECT_EQ(rtu->device, "/dev/ttyUSB0");
  EXPECT_EQ(rtu->baud, 19200);
  EXPECT_EQ(rtu->parity, 'E');
  EXPECT_EQ(rtu->unit_id, 7);
  for (const char* bad : {"tcp:1502", "tcp:host:0", "tcp:host:70000", "rtu:/dev/ttyS0:19200:7E1:1",
                          "rtu:/dev/ttyS0:19200:8N1:0", "rtu:/dev/ttyS0:19200:8N1:248", "rtu:/dev/ttyS0:8N1:1",
                          "udp:host:1"}) {
    EXPECT_FALSE(modbus::parse_endpoint(bad, error)) << bad;
    EXPECT_FALSE(error.empty());
  }
}

// The operator's console: lines typed at chosen jiffies, everything answered kept.
class OperatorConsole final : public hal::ConsolePort {
 public:
  std::size_t read(char* destination, std::size_t capacity) override {
    const std::size_t n = pending.size() < capacity ? pending.size() : capacity;
    std::memcpy(destination, pending.data(), n);
    pending.erase(0, n);
    return n;
  }
  void write(const char* data, std::size_t length) override { output.append(data, length); }
  std::string pending;
  std::string output;
};

struct Plc {
  modbus::PlcMailbox mailbox;
  OperatorConsole console;
  modbus::PlcConsole port{console, mailbox};
  hal::host::LockstepSession session{sim::default_scene(), 1};
  std::uint16_t registers[125] = {};
  std::size_t count = 0;

  Exception send(const std::vector<std::uint8_t>& request) {
    return mailbox.serve(request.data(), request.size(), registers, &count).exception;
  }
  std::uint16_t command_register() {
    EXPECT_EQ(send(pdu(modbus::kReadHoldingRegisters, {5, 1})), Exception::none);
    return registers[0];
  }
  std::vector<std::uint16_t> inputs() {
    EXPECT_EQ(send(pdu(modbus::kReadInputRegisters, {0, 18})), Exception::none);
    return std::vector<std::uint16_t>(registers, registers + 18);
  }
  firmware::Outputs jiffy() {
    port.before_jiffy();
    const firmware::Outputs out = session.step(port);
    port.after_jiffy(session.indicator(), out);
    return out;
  }
  // Runs until register 5 answers (at most `limit` jiffies).
  std::uint16_t until_answered(int limit = 3000) {
    for (int i = 0; i < limit && command_register() == modbus::kCommandRunning; ++i) jiffy();
    return command_register();
  }
};

std::int32_t int32_at(const std::vector<std::uint16_t>& r, std::size_t at) {
  return std::int32_t((std::uint32_t(r[at]) << 16) | r[at + 1]);
}

TEST(PlcConsole, APlcDoseGoesThroughTheConsolePathAndItsResultFillsTheRegisters) {
  Plc plc;
  plc.jiffy();
  ASSERT_EQ(plc.send(write_multiple(0, {0, 2000, 0, 0, 0, 1})), Exception::none);
  EXPECT_EQ(plc.command_register(), modbus::kCommandRunning);
  plc.jiffy();
  EXPECT_EQ(plc.inputs()[modbus::input::state], 1u);  // dosing
  EXPECT_EQ(plc.until_answered(), 0u);
  const std::string& out = plc.console.output;
  const std::size_t at = out.find("RESULT ");
  ASSERT_NE(at, std::string::npos) << out;
  modbus::ResultFields result;
  ASSERT_TRUE(modbus::parse_result_line(out.substr(at, out.find('\n', at) - at).c_str(), result));
  const std::vector<std::uint16_t> r = plc.inputs();
  EXPECT_EQ(r[modbus::input::result_seq], 1u);
  EXPECT_EQ(int32_at(r, modbus::input::result_final_dg), result.final_g * 10);
  EXPECT_EQ(int32_at(r, modbus::input::result_error_dg), result.error_g * 10);
  EXPECT_EQ(std::uint32_t(int32_at(r, modbus::input::result_time_ms)), result.time_ms);
}

TEST(PlcConsole, APlcMaterialIsSelectedBeforeItsDoseAndRegister5AnswersTheDose) {
  Plc plc;
  plc.jiffy();
  ASSERT_EQ(plc.send(write_multiple(0, {0, 1000, 0, 7, 0, 1})), Exception::none);
  for (int i = 0; i < 5; ++i) plc.jiffy();
  EXPECT_EQ(plc.command_register(), modbus::kCommandRunning) << "the material's OK is not the dose's";
  EXPECT_EQ(plc.until_answered(), 0u);
  const std::string& out = plc.console.output;
  const std::size_t selected = out.find("MATERIAL n=7 name=material7");
  ASSERT_NE(selected, std::string::npos) << out;
  EXPECT_LT(selected, out.find("RESULT target=1000")) << out;
  EXPECT_NE(out.find(" material=7 "), std::string::npos) << out;
  EXPECT_EQ(plc.session.indicator().settings().materials.selected(), 7u);
}

TEST(PlcConsole, OneSidesCommandAtATimeAndAbortFromThePlcCutsAnOperatorsDose) {
  Plc plc;
  plc.console.pending = "dose 3000\n";
  plc.jiffy();
  ASSERT_EQ(plc.send(pdu(modbus::kWriteSingleRegister, {5, 3})), Exception::none);  // tare
  for (int i = 0; i < 20; ++i) plc.jiffy();
  EXPECT_EQ(plc.command_register(), modbus::kCommandRunning) << "the PLC's tare waits for the operator's dose";
  EXPECT_EQ(plc.console.output.find("ERR 3 busy"), std::string::npos);
  EXPECT_EQ(plc.send(pdu(modbus::kWriteSingleRegister, {5, 2})), Exception::none);  // abort replaces it
  EXPECT_EQ(plc.until_answered(10), 0u);
  EXPECT_NE(plc.console.output.find("ERR 3 aborted\nOK\n"), std::string::npos) << plc.console.output;
  EXPECT_EQ(plc.inputs()[modbus::input::valve], 0u);

  // While the PLC's dose runs the operator's line waits, then gets its own answer.
  ASSERT_EQ(plc.send(write_multiple(0, {0, 1000, 1, 0, 0, 1})), Exception::none);
  plc.jiffy();
  plc.console.pending = "version\n";
  plc.jiffy();
  EXPECT_EQ(plc.console.pending, "version\n");
  EXPECT_EQ(plc.until_answered(), 0u);
  plc.jiffy();
  plc.jiffy();
  EXPECT_TRUE(plc.console.pending.empty());
  const std::string& out = plc.console.output;
  EXPECT_LT(out.find("RESULT target=1000"), out.rfind(firmware::kFirmwareVersion)) << out;
}

TEST(PlcConsole, TheWatchdogAbortsASilentPlcsDoseWithTheValveClosed) {
  Plc plc;
  plc.console.pending = "param plc_watchdog_ms 1000\n";
  for (int i = 0; i < 3; ++i) plc.jiffy();
  ASSERT_EQ(plc.send(write_multiple(0, {0, 5000, 0, 0, 0, 1})), Exception::none);
  // No request from here on: the register reads below go straight to the map, not the mailbox.
  int jiffies = 0;
  bool valve_opened = false;
  for (; jiffies < 300 && !plc.port.watchdog_fired(); ++jiffies) {
    valve_opened |= plc.jiffy().valve != firmware::ValveCommand::closed;
  }
  EXPECT_TRUE(valve_opened);
  EXPECT_TRUE(plc.port.watchdog_fired());
  EXPECT_EQ(jiffies, 100);  // 1000 ms of 10 ms jiffies without a request
  const firmware::Outputs out = plc.jiffy();
  EXPECT_EQ(out.valve, firmware::ValveCommand::closed);
  EXPECT_EQ(out.state, firmware::IndicatorState::idle);
  EXPECT_NE(plc.console.output.find("ERR 3 aborted"), std::string::npos) << plc.console.output;
  plc.jiffy();
  EXPECT_EQ(plc.command_register(), 3u);
}

}  // namespace
