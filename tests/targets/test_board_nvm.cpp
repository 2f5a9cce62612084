// A board's settings storage that fails at run time (a full disk, a worn EEPROM: CuttableNvm with a
// cut armed) is the fault nvm_error, reported to the indicator through the next jiffy's Inputs: the
// command that changed the settings answers ERR instead of OK, and a recording replays it exactly.
#include <gtest/gtest.h>

#include <cstdio>
#include <deque>
#include <string>

#include "dynweigh/firmware/settings_slots.hpp"
#include "dynweigh/hal/host/cuttable_nvm.hpp"
#include "dynweigh/hal/host/inputs_recording.hpp"
#include "dynweigh/hal/host/lockstep_session.hpp"
#include "dynweigh/hal/host/scripted_console.hpp"
#include "dynweigh/sim/scene.hpp"

namespace dynweigh {
namespace {

using firmware::Fault;

// Sends lines one at a time, each once the previous command has finished; returns what was printed.
template <typename Step>
std::string run_lines(std::deque<std::string> lines, Step&& step) {
  std::string output;
  hal::host::ScriptedConsole console(
      [&](std::string& line) {
        if (lines.empty()) return false;
        line = lines.front();
        lines.pop_front();
        return true;
      },
      [&](const char* data, std::size_t n) { output.append(data, n); });
  for (int jiffy = 0; jiffy < 1000; ++jiffy) {
    const firmware::Outputs out = step(console);
    console.set_indicator_busy(out.busy);
    if (console.input_ended() && !out.busy) break;
  }
  return output;
}

struct FailingStorageBoard : ::testing::Test {
  hal::host::CuttableNvm nvm{firmware::kSettingsSlotsBytes};
  hal::host::SlottedSettingsStore store{nvm};
  hal::host::LockstepSession session{sim::default_scene(), 1, std::nullopt, &store};
  std::string run(std::deque<std::string> lines) {
    return run_lines(std::move(lines), [&](hal::ConsolePort& console) { return session.step(console); });
  }
};

TEST_F(FailingStorageBoard, ASavedChangeAnswersOk) {
  EXPECT_EQ(run({"param fall_mm 1500"}), "fall_mm=1500\nOK\n");
  EXPECT_EQ(session.indicator().fault(), Fault::none);
  firmware::PersistentSettings stored;
  ASSERT_TRUE(store.load(stored));
  EXPECT_EQ(stored.parameters.get(firmware::ParameterId::fall_mm), 1500.0f);
}

TEST_F(FailingStorageBoard, AFailedSaveIsTheFaultNvmErrorNotOk) {
  nvm.arm_cut(10);  // the next write stops after 10 bytes: the save fails
  EXPECT_EQ(run({"param fall_mm 1500"}), "fall_mm=1500\nERR 4 fault nvm_error\n");
  EXPECT_EQ(session.indicator().fault(), Fault::nvm_error);
  const std::string status = run({"status"});
  EXPECT_EQ(status.rfind("STATUS state=fault ", 0), 0u) << status;
  EXPECT_NE(status.find(" fault=nvm_error\nOK\n"), std::string::npos) << status;
  EXPECT_EQ(run({"dose 1000"}), "ERR 4 fault active\n");
  // The storage works again: clearfault, and the next change is saved and answered OK.
  EXPECT_EQ(run({"clearfault", "param fall_mm 1600"}), "OK\nfall_mm=1600\nOK\n");
  EXPECT_EQ(session.indicator().fault(), Fault::none);
}

TEST_F(FailingStorageBoard, ARecordingReplaysTheFailedSave) {
  const std::string path = ::testing::TempDir() + "failed_save.rec";
  {
    hal::host::InputsRecordingWriter recording(path, session.indicator(), "test");
    session.record_to(&recording);
    run_lines({"param fall_mm 1500"}, [&](hal::ConsolePort& console) { return session.step(console); });
    nvm.arm_cut(10);
    run_lines({"param fall_mm 1600", "status"}, [&](hal::ConsolePort& console) { return session.step(console); });
    session.record_to(nullptr);
  }
  hal::host::InputsRecordingReader reader(path);
  firmware::Indicator replayed(reader.settings());
  std::string printed;
  int failed_saves = 0;
  for (hal::host::RecordedJiffy j; reader.next(j);) {
    failed_saves += j.settings_save == firmware::SettingsSave::failed;
    const firmware::Outputs out = replayed.step(j.inputs());
    char buffer[512];
    for (std::size_t n; (n = replayed.drain_console(buffer, sizeof buffer)) > 0;) printed.append(buffer, n);
    EXPECT_TRUE(hal::host::same_outputs(out, j.outputs, j.has_telemetry)) << "jiffy " << j.jiffy;
  }
  EXPECT_EQ(failed_saves, 1);
  EXPECT_EQ(replayed.fault(), Fault::nvm_error);
  EXPECT_NE(printed.find("fall_mm=1600\nERR 4 fault nvm_error\nSTATUS state=fault"), std::string::npos) << printed;
  std::remove(path.c_str());
}

}  // namespace
}  // namespace dynweigh
