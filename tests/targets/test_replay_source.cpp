// `dynweigh plant --replay FILE`: a readtestdata capture or a CSV with a raw column.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <string>

#include "replay_source.hpp"

namespace dynweigh::tools {
namespace {

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

}  // namespace
}  // namespace dynweigh::tools
