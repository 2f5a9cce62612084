// What the fuzz targets of fuzz/ found, pinned as ordinary tests: each fails
// on the code as it was before its fix.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "dynweigh/firmware/persistent_settings.hpp"
#include "dynweigh/sim/scene_file.hpp"
#include "support/console_session.hpp"

namespace dynweigh::testing {
namespace {

std::size_t count_lines(const std::string& output, const std::string& start) {
  std::size_t n = 0;
  for (const std::string& line : lines_of(output)) n += line.rfind(start, 0) == 0 ? 1 : 0;
  return n;
}

// Before: `valve 2` then `dose 1000` dosed, closed at the cutoff, printed the RESULT, and then the
// manual command opened the valve again; the fill ran on unattended.
TEST(FuzzFindings, DoseOverAManuallyOpenedValveIsRefusedAndTheValveStaysAsCommanded) {
  ConsoleSession c;
  ASSERT_EQ(c.run({"valve 2"}), "OK\n");
  EXPECT_EQ(c.run({"dose 1000"}), "ERR 3 valve open (valve 0 first)\n");
  ASSERT_EQ(c.run({"valve 0"}), "OK\n");
  c.idle(300);  // what was in flight lands
  const std::string dosed = c.run({"dose 1000"});
  ASSERT_EQ(count_lines(dosed, "RESULT"), 1u) << dosed;
  const double at_result_kg = c.trace().back().static_kg;
  c.idle(300);
  EXPECT_EQ(c.trace().back().valve, 0);
  EXPECT_NEAR(c.trace().back().static_kg, at_result_kg, 1e-9) << "material still flows after the result";
}

// Before: a line of blanks or a NUL byte was "empty" (no answer) unless lines were typed ahead
// beyond the queue, when it was answered `ERR 3 busy`; a NUL cut a line short, so `valve 2<NUL>x`
// ran `valve 2`.
TEST(FuzzFindings, BlankAndNulBytesNeverMakeOrCutACommand) {
  ConsoleSession c;
  const std::string typed_ahead = std::string("version\nversion\nversion\nversion\n \t \n") + '\0' + "\n";
  const std::string answers = c.send_raw(typed_ahead, 3);
  EXPECT_EQ(count_lines(answers, "OK"), 4u) << answers;
  EXPECT_EQ(count_lines(answers, "ERR"), 0u) << answers;
  EXPECT_EQ(c.send_raw(std::string("valve 2") + '\0' + "x\n", 3).rfind("ERR 2", 0), 0u);
  EXPECT_EQ(c.send_raw(std::string("ver") + '\0' + "sion\n", 3), std::string("dynweigh ") + firmware::kFirmwareVersion + "\nOK\n");
}

firmware::PersistentSettings decoded_after_encoding(const firmware::PersistentSettings& settings) {
  std::uint8_t record[firmware::kSettingsRecordSize];
  EXPECT_EQ(firmware::encode_settings(settings, record, sizeof record), firmware::kSettingsRecordSize);
  firmware::PersistentSettings decoded;
  EXPECT_TRUE(firmware::decode_settings(record, sizeof record, decoded));
  return decoded;
}

// Before: a record with an intact CRC but a NaN zero or an infinite span decoded as a valid
// calibration, and the indicator weighed with it. (The zero is whole counts and a fraction now: a
// fraction outside [0, 1) is no zero `zero` takes.)
TEST(FuzzFindings, ACalibrationNoCommandCanProduceIsDropped) {
  for (const auto& [zero, span] : {std::pair{NAN, 20.0f}, std::pair{1.5f, 20.0f}, std::pair{0.0f, INFINITY},
                                   std::pair{0.0f, -3.0f}}) {
    firmware::PersistentSettings settings;
    settings.calibration = {200000, zero, span, true, true};
    settings.parameters.set(firmware::ParameterId::fall_mm, 1500.0f);
    const firmware::PersistentSettings decoded = decoded_after_encoding(settings);
    EXPECT_FALSE(decoded.calibration.valid()) << zero << " " << span;
    EXPECT_FALSE(decoded.calibration.zero_set || decoded.calibration.span_set);
    EXPECT_EQ(decoded.parameters.get(firmware::ParameterId::fall_mm), 1500.0f);  // the rest is kept
  }
}

// Before: any finite correction was trusted; `learn` would print 1e30 g through a float-to-integer
// conversion out of range (undefined behaviour in TextWriter::write_decimal).
TEST(FuzzFindings, ALearningCorrectionBeyondWhatItsFillsCanLearnIsDropped) {
  firmware::PersistentSettings settings;
  firmware::LearningTable::Entry& kept = settings.learning.entry(0);
  kept = {{1, 2, 3}, 2 * firmware::LearningTable::kMaximumStepG, 2, true};
  firmware::LearningTable::Entry& impossible = settings.learning.entry(1);
  impossible = {{4, 5, 6}, 1e30f, 2, true};
  const firmware::PersistentSettings decoded = decoded_after_encoding(settings);
  EXPECT_TRUE(decoded.learning.entry(0).used);
  EXPECT_EQ(decoded.learning.entry(0).correction_g, 2 * firmware::LearningTable::kMaximumStepG);
  EXPECT_FALSE(decoded.learning.entry(1).used);
  EXPECT_EQ(decoded.learning.entry(1).correction_g, 0.0f);
}

std::string refusal(const std::string& text) {
  try {
    sim::parse_scene_json(text, "x.json");
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "(accepted)";
}

// Before: a key holding a newline gave a two-line message, and a number beyond double escaped as
// nlohmann's out_of_range without the file's name.
TEST(FuzzFindings, SceneRefusalsAreOneLineNamingTheFile) {
  const std::string newline_key = refusal("{\"a\\nb\": 1}");
  EXPECT_EQ(newline_key.find('\n'), std::string::npos) << newline_key;
  EXPECT_EQ(newline_key.rfind("x.json: ", 0), 0u) << newline_key;
  const std::string overflow = refusal("{\"g\": 1e400}");
  EXPECT_EQ(overflow.rfind("x.json: not valid JSON", 0), 0u) << overflow;
  const std::string long_key = refusal("{\"" + std::string(5000, 'k') + "\": 1}");
  EXPECT_LT(long_key.size(), 400u);
}

// Before: the whole file was read into memory whatever its size.
TEST(FuzzFindings, AnEnormousSceneFileIsRefusedWithoutReadingIt) {
  const std::string path = ::testing::TempDir() + "dynweigh_enormous_scene.json";
  std::FILE* f = std::fopen(path.c_str(), "wb");
  ASSERT_NE(f, nullptr);
  const std::string chunk(1 << 16, ' ');
  for (int i = 0; i < 40; ++i) std::fwrite(chunk.data(), 1, chunk.size(), f);  // 2.5 MiB of blanks
  std::fclose(f);
  try {
    sim::load_scene_file(path);
    ADD_FAILURE() << "an enormous scene file was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("not a scene file"), std::string::npos) << e.what();
  }
  std::remove(path.c_str());
}

}  // namespace
}  // namespace dynweigh::testing
