// The discharge cycle on the in-process plant: `discharge` empties the hopper and proves the gate
// closed; a gate that sticks shut or open, and an opened gate that lets nothing out, are faults that
// leave the valve and the gate closed; with auto_discharge 1 fill and discharge cycles run on a
// refilled silo without a fault and without the empty hopper's reading drifting.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include "dynweigh/hal/host/inputs_recording.hpp"
#include "support/console_session.hpp"

namespace dynweigh::testing {
namespace {

constexpr double kDivisionG = 1.0;  // the default scene's scale interval d

bool has_line(const std::string& output, const std::string& line) {
  for (const std::string& l : lines_of(output)) {
    if (l == line) return true;
  }
  return false;
}

std::string status_of(ConsoleSession& s) { return s.run({"status"}); }

// The outputs of the last jiffy and the plant say the same: valve shut, gate shut.
void expect_everything_closed(ConsoleSession& s) {
  EXPECT_EQ(s.session().last_record().outputs.valve, firmware::ValveCommand::closed);
  s.idle(100);  // a gate module strokes in 0.5 s
  EXPECT_EQ(s.session().plant().gate_feedback(), sim::GateFeedback::closed);
  EXPECT_EQ(s.session().plant().valve_feedback(), firmware::ValvePosition::closed);
}

TEST(Discharge, EmptiesTheHopperAndProvesTheGateClosed) {
  ConsoleSession s;
  ASSERT_NE(s.run({"dose 2000"}).find("RESULT "), std::string::npos);
  ASSERT_GT(s.session().plant().truth().static_kg, 1.9);
  const std::string out = s.run({"discharge"});
  EXPECT_EQ(out, "OK\n");
  const sim::PlantTruth truth = s.session().plant().truth();
  EXPECT_GT(truth.discharged_kg, 1.9);
  EXPECT_LT(truth.static_kg * 1000.0, 20.0);  // empty_band_g
  EXPECT_EQ(s.session().plant().gate_feedback(), sim::GateFeedback::closed);
  const std::string status = status_of(s);
  EXPECT_NE(status.find("state=idle"), std::string::npos) << status;
  EXPECT_NE(status.find("fault=none"), std::string::npos) << status;
  EXPECT_LE(std::fabs(std::stod(field(lines_of(status)[0], "weight"))), 20.0) << status;
}

TEST(Discharge, AGateStuckShutIsAFaultWithEverythingClosed) {
  ConsoleSession s;
  ASSERT_NE(s.run({"dose 2000"}).find("RESULT "), std::string::npos);
  s.session().plant().jam_gate(true);
  EXPECT_TRUE(has_line(s.run({"discharge"}), "ERR 4 fault gate_not_open"));
  EXPECT_NE(status_of(s).find("fault=gate_not_open"), std::string::npos);
  EXPECT_GT(s.session().plant().truth().static_kg, 1.9);  // nothing let out
  s.session().plant().jam_gate(false);  // freed: the gate follows its command, which is closed
  expect_everything_closed(s);
  EXPECT_TRUE(has_line(s.run({"dose 1000"}), "ERR 4 fault active"));
}

TEST(Discharge, AGateStuckOpenIsAFaultWithTheGateCommandedClosed) {
  ConsoleSession s;
  ASSERT_NE(s.run({"dose 2000"}).find("RESULT "), std::string::npos);
  // Stop the script once the gate is open, then jam it there.
  s.run({"discharge"}, 60);
  ASSERT_EQ(s.session().plant().gate_feedback(), sim::GateFeedback::open);
  s.session().plant().jam_gate(true);
  s.idle(400);
  EXPECT_NE(status_of(s).find("fault=gate_not_closed"), std::string::npos);
  s.session().plant().jam_gate(false);
  expect_everything_closed(s);
}

TEST(Discharge, AnOpenedGateThatLetsNothingOutTimesOut) {
  sim::Scene scene = sim::default_scene();
  scene.gate.discharge_kg_s = 0.0;  // the outlet blocked
  ConsoleSession s(scene);
  ASSERT_NE(s.run({"dose 2000"}).find("RESULT "), std::string::npos);
  ASSERT_EQ(s.run({"param discharge_timeout_s 3"}), "discharge_timeout_s=3\nOK\n");
  std::uint32_t open_jiffies = 0;
  s.run({"discharge"}, 1);
  for (int i = 0; i < 600 && s.session().last_record().outputs.busy; ++i) {
    s.step();
    if (s.session().plant().gate_feedback() == sim::GateFeedback::open) ++open_jiffies;
  }
  EXPECT_GT(open_jiffies, 200u);  // opened, proven open, held open until the timeout
  EXPECT_LT(open_jiffies, 320u);  // and no longer: 3 s
  EXPECT_NE(status_of(s).find("fault=not_empty"), std::string::npos);
  expect_everything_closed(s);
}

TEST(Discharge, AutoDischargeRunsFillAndDischargeCyclesOnARefilledSilo) {
  sim::Scene scene = sim::default_scene();
  scene.silo.refill_below_kg = 6.0;
  scene.silo.refill_rate_kg_s = 5.0;
  ConsoleSession s(scene);
  ASSERT_EQ(s.run({"param auto_discharge 1"}), "auto_discharge=1\nOK\n");
  constexpr int kCycles = 12;  // 36 kg: twice what the silo holds
  double first_empty_g = 0.0;
  for (int i = 0; i < kCycles; ++i) {
    const std::string out = s.run({"dose 3000"});
    const auto lines = lines_of(out);
    ASSERT_EQ(lines.size(), 2u) << "cycle " << i << ":\n" << out;
    ASSERT_EQ(lines[0].rfind("RESULT ", 0), 0u) << out;
    ASSERT_EQ(lines[1], "OK") << out;
    EXPECT_EQ(s.session().plant().gate_feedback(), sim::GateFeedback::closed);
    EXPECT_LT(s.session().plant().truth().static_kg * 1000.0, 20.0) << "cycle " << i;
    s.idle(100);
    const double empty_g = double(s.session().last_record().outputs.filtered_g);
    if (i == 0) first_empty_g = empty_g;
    EXPECT_LE(std::fabs(empty_g - first_empty_g), kDivisionG) << "cycle " << i;
  }
  EXPECT_GT(s.session().plant().truth().refilled_kg, 10.0);
  const std::string stats = s.run({"stats"});
  EXPECT_EQ(field(lines_of(stats)[0], "count"), std::to_string(kCycles)) << stats;
  EXPECT_EQ(field(lines_of(stats)[0], "gate_cycles"), std::to_string(kCycles)) << stats;
  EXPECT_NE(status_of(s).find("fault=none"), std::string::npos);
}

// The gate's feedback is an input like the valve's: a recorded discharge replays bit for bit (a
// replay that saw the gate closed would end in gate_not_open) and the gate's command is compared.
TEST(Discharge, ARecordedDischargeReplaysWithItsGate) {
  const std::string path = ::testing::TempDir() + "discharge" + std::to_string(::getpid()) + ".rec";
  ConsoleSession s;
  std::size_t gate_open_jiffies = 0;
  {
    hal::host::InputsRecordingWriter recording(path, s.session().indicator(), "test");
    s.session().record_to(&recording);
    ASSERT_NE(s.run({"dose 2000"}).find("RESULT "), std::string::npos);
    ASSERT_EQ(s.run({"discharge"}), "OK\n");
    s.session().record_to(nullptr);
  }
  hal::host::InputsRecordingReader reader(path);
  firmware::Indicator replayed(reader.settings());
  replayed.resume_sequence(reader.last_sequence());
  std::size_t jiffies = 0;
  for (hal::host::RecordedJiffy j; reader.next(j); ++jiffies) {
    if (j.gate_position == firmware::GatePosition::open) ++gate_open_jiffies;
    const firmware::Outputs out = replayed.step(j.inputs());
    ASSERT_TRUE(hal::host::same_outputs(out, j.outputs, true)) << "jiffy " << jiffies;
  }
  EXPECT_GT(jiffies, 50u);
  EXPECT_GT(gate_open_jiffies, 10u);
  EXPECT_EQ(replayed.fault(), firmware::Fault::none);
  std::remove(path.c_str());
}

TEST(Discharge, IsListedByHelp) {
  ConsoleSession s;
  EXPECT_NE(s.run({"help"}).find("\ndischarge "), std::string::npos);
}

}  // namespace
}  // namespace dynweigh::testing
