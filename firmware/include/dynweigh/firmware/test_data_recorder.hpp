#pragma once
// The test-data recorder of the thesis' indicator (its section 2.2): 1000 jiffies of raw counts,
// filtered weight and valve marker, started by `starttestdata` or a dose, read by `readtestdata`.
#include <cstddef>
#include <cstdint>

namespace dynweigh::firmware {

class TestDataRecorder {
 public:
  static constexpr std::size_t kRecords = 1000;

  struct Record {
    std::int32_t raw_counts;
    std::int32_t filtered_g;
    std::uint8_t marker;  // 0 closed, 1 half, 2 open
  };

  void start() { count_ = 0; recording_ = true; has_data_ = true; }
  bool recording() const { return recording_; }
  bool has_data() const { return has_data_; }
  std::size_t count() const { return count_; }

  void record(std::int32_t raw_counts, std::int32_t filtered_g, std::uint8_t marker) {
    if (!recording_) return;
    raw_[count_] = raw_counts;
    filtered_[count_] = filtered_g;
    marker_[count_] = marker;
    if (++count_ == kRecords) recording_ = false;
  }

  Record at(std::size_t jiffy) const { return {raw_[jiffy], filtered_[jiffy], marker_[jiffy]}; }

 private:
  std::int32_t raw_[kRecords] = {};
  std::int32_t filtered_[kRecords] = {};
  std::uint8_t marker_[kRecords] = {};
  std::size_t count_ = 0;
  bool recording_ = false;
  bool has_data_ = false;
};

}  // namespace dynweigh::firmware
