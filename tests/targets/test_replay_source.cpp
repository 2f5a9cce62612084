// `dynweigh plant --replay FILE` reads its samples through the one capture reader (the same as
// `dynweigh replay`): a readtestdata capture, a CSV with a raw column, or an inputs recording; any
// other binary file is refused.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "dynweigh/hal/host/inputs_recording.hpp"
#include "recorded_samples.hpp"

namespace dynweigh::tools {
namespace {

std::vector<std::int32_t> load_replay_samples(const std::string& path) {
  std::vector<std::int32_t> raw;
  for (const RecordedSample& sample : load_recorded_samples(path).samples) raw.push_back(sample.raw_counts);
  return raw;
}

std::string write_temp(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + name + std::to_string(::getpid());
  std::ofstream(path) << text;
  return path;
}

TEST(ReplaySource, ReadsAReadtestdataCaptureSkippingOtherLines) {
  const auto path = write_temp("capture", "starttestdata 50 600\nOK\n0 12000 0 0\n1 12003 2 0\r\n2 -5 -12000 2\nOK\n");
  const auto samples = load_replay_samples(path);
  ASSERT_EQ(samples.size(), 3u);
  EXPECT_EQ(samples[0], 12000);
  EXPECT_EQ(samples[1], 12003);
  EXPECT_EQ(samples[2], -5);
  std::remove(path.c_str());
}

TEST(ReplaySource, ReadsTheRawColumnOfACsv) {
  const auto path = write_temp("csv", "t_s,jiffy,static_kg,in_flight_kg,force_n,raw,filtered_g,valve\n"
                                      "0.00,0,,,,12000,0.0,0\n0.01,1,,,,12010,1.5,2\n");
  const auto samples = load_replay_samples(path);
  ASSERT_EQ(samples.size(), 2u);
  EXPECT_EQ(samples[1], 12010);
  std::remove(path.c_str());
}

TEST(ReplaySource, RefusesFilesWithoutSamples) {
  const auto no_raw = write_temp("noraw", "a,b,c\n1,2,3\n");
  EXPECT_THROW(load_replay_samples(no_raw), std::runtime_error);
  const auto empty = write_temp("empty", "OK\n");
  EXPECT_THROW(load_replay_samples(empty), std::runtime_error);
  EXPECT_THROW(load_replay_samples("/nonexistent/file"), std::runtime_error);
  std::remove(no_raw.c_str());
  std::remove(empty.c_str());
}

TEST(ReplaySource, ReadsEachJiffysSampleOfAnInputsRecording) {
  const std::string path = ::testing::TempDir() + "inputs" + std::to_string(::getpid()) + ".rec";
  {
    hal::host::InputsRecordingWriter writer(path, firmware::PersistentSettings{}, "test");
    for (std::uint32_t k = 0; k < 250; ++k) {
      hal::host::RecordedJiffy jiffy;
      jiffy.jiffy = k;
      jiffy.load_cell.raw_counts = std::int32_t(12000 + 7 * k) * (k % 2 ? -1 : 1);
      jiffy.console_rx = k == 3 ? "dose 100\n1 2 3 4\n" : "";  // text inside must not be read as samples
      writer.write(jiffy);
    }
  }
  const auto samples = load_replay_samples(path);
  ASSERT_EQ(samples.size(), 250u);
  for (std::uint32_t k = 0; k < 250; ++k) EXPECT_EQ(samples[k], std::int32_t(12000 + 7 * k) * (k % 2 ? -1 : 1));
  std::remove(path.c_str());
}

TEST(ReplaySource, RefusesOtherBinaryFiles) {
  const auto binary = write_temp("binary", std::string("\x7f" "ELF\x02\x01\x01\n1 2 3 4\n0 5 6 0\n"));
  EXPECT_THROW(load_replay_samples(binary), std::runtime_error);
  const auto nul = write_temp("nul", std::string("0 12000 0 0\n\0\0\0\n", 16));
  EXPECT_THROW(load_replay_samples(nul), std::runtime_error);
  std::remove(binary.c_str());
  std::remove(nul.c_str());
}

}  // namespace
}  // namespace dynweigh::tools
