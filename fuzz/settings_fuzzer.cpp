// Fuzz target: arbitrary bytes as the non-volatile memory the indicator reads its calibration,
// parameters and learning table from (settings_slots.hpp over persistent_settings.hpp).
//
// The input is tried as it is, and again with both CRCs of each slot recomputed, so the fuzzer
// reaches the field decoding behind them (a CRC only guards against damage, not against a record
// that a bad firmware version or a bit flip before the CRC was computed wrote).
//
// Invariants: a load either refuses (settings untouched) or yields valid settings: every parameter
// within its range, a calibration that is set finite (a set span positive), learning corrections
// finite and within what their fills can have learned; valid settings encode and decode to
// themselves, save into the same memory and load back; an indicator started with them answers
// `status`, `param` and `learn`.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <utility>
#include <vector>

#include "dynweigh/firmware/indicator.hpp"
#include "dynweigh/firmware/little_endian.hpp"
#include "dynweigh/firmware/settings_slots.hpp"

namespace {

using namespace dynweigh::firmware;

[[noreturn]] void violated(const char* what) {
  std::fprintf(stderr, "settings invariant violated: %s\n", what);
  std::abort();
}

class MemoryNvm final : public NvmBlock {
 public:
  explicit MemoryNvm(std::vector<std::uint8_t> bytes) : bytes_(std::move(bytes)) {}
  std::size_t size() const override { return bytes_.size(); }
  bool read(std::size_t offset, std::uint8_t* data, std::size_t length) const override {
    if (offset > bytes_.size() || length > bytes_.size() - offset) return false;
    std::memcpy(data, bytes_.data() + offset, length);
    return true;
  }
  bool write(std::size_t offset, const std::uint8_t* data, std::size_t length) override {
    if (offset > bytes_.size() || length > bytes_.size() - offset) return false;
    std::memcpy(bytes_.data() + offset, data, length);
    return true;
  }

 private:
  std::vector<std::uint8_t> bytes_;
};

void put_u32(std::uint8_t* p, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = std::uint8_t(v >> (8 * i));
}

// The two CRCs as encode_settings and encode_slot compute them, over whatever the fields hold.
void fix_record_crc(std::uint8_t* record) {
  put_u32(record + 12, crc32(record + 16, kSettingsRecordSize - 16) ^ crc32(record, 12));
}
void fix_slot_crcs(std::uint8_t* slot) {
  fix_record_crc(slot + kSlotHeaderSize);
  put_u32(slot + 12, crc32(slot + 4, 8) ^ crc32(slot + kSlotHeaderSize, kSettingsRecordSize));
}

void check_valid(const PersistentSettings& s) {
  for (std::size_t i = 0; i < kParameterCount; ++i) {
    const ParameterSpec& spec = parameter_spec(static_cast<ParameterId>(i));
    const float v = s.parameters.raw()[i];
    if (!(v >= spec.minimum && v <= spec.maximum)) violated("a parameter out of its range");
    if (spec.choices && v != std::floor(v)) violated("a choice parameter that is not a whole number");
  }
  const Calibration& cal = s.calibration;
  if ((cal.zero_set || cal.span_set) &&
      !(cal.zero_fraction >= 0.0f && cal.zero_fraction < 1.0f && std::isfinite(cal.counts_per_gram))) {
    violated("a calibration that is not finite or not a zero of whole counts and a fraction");
  }
  if (cal.span_set && !(cal.counts_per_gram > 0.0f)) violated("a span that is not positive");
  for (std::size_t i = 0; i < LearningTable::kEntries; ++i) {
    const LearningTable::Entry& e = s.learning.entry(i);
    // Each fill moves a correction by at most kMaximumStepG.
    if (!std::isfinite(e.correction_g) || std::fabs(e.correction_g) > LearningTable::kMaximumStepG * float(e.fills)) {
      violated("a learning correction beyond what its fills can have learned");
    }
  }
}

std::vector<std::uint8_t> encoded(const PersistentSettings& s) {
  std::vector<std::uint8_t> bytes(kSettingsRecordSize);
  if (encode_settings(s, bytes.data(), bytes.size()) != kSettingsRecordSize) violated("valid settings do not encode");
  return bytes;
}

void check_round_trip(const PersistentSettings& s) {
  const std::vector<std::uint8_t> bytes = encoded(s);
  PersistentSettings back;
  if (!decode_settings(bytes.data(), bytes.size(), back)) violated("encoded settings do not decode");
  if (encoded(back) != bytes) violated("settings do not survive an encode/decode round trip");
}

void check_indicator_runs(const PersistentSettings& s) {
  Indicator indicator(s);
  const char commands[] = "status\nparam\nlearn\nversion\n";
  Inputs in;
  in.load_cell.raw_counts = 100000;
  in.console_rx = commands;
  in.console_rx_length = sizeof commands - 1;
  char drained[TextWriter::kCapacity];
  for (std::uint32_t jiffy = 0; jiffy < 3; ++jiffy) {
    in.jiffy = jiffy;
    in.load_cell.counter = std::uint16_t(jiffy);
    indicator.step(in);
    in.console_rx_length = 0;
    indicator.drain_console(drained, sizeof drained);
  }
}

void check_memory(std::vector<std::uint8_t> image) {
  MemoryNvm nvm(std::move(image));
  SettingsSlots slots(nvm);
  PersistentSettings loaded;
  if (!slots.load(loaded)) {
    if (slots.newest_slot() != -1) violated("a refused load names a slot");
    return;
  }
  if (nvm.size() < kSettingsSlotsBytes) violated("settings loaded from a memory smaller than two slots");
  check_valid(loaded);
  check_round_trip(loaded);
  const std::uint32_t before = slots.newest_sequence();
  if (!slots.save(loaded)) violated("valid settings do not save");
  if (slots.newest_sequence() != before + 1) violated("a save does not take the next sequence number");
  PersistentSettings again;
  if (!slots.load(again) || encoded(again) != encoded(loaded)) violated("saved settings do not load back");
  check_indicator_runs(loaded);
}

void check_record(const std::uint8_t* data, std::size_t size) {
  PersistentSettings decoded;
  if (!decode_settings(data, size, decoded)) return;
  // An older version's record is shorter than today's; none is shorter than the length it declares.
  if (size < get_u32(data + 8)) violated("a record shorter than its declared length decoded");
  check_valid(decoded);
  check_round_trip(decoded);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  check_memory(std::vector<std::uint8_t>(data, data + size));
  check_record(data, size);
  if (size >= kSettingsRecordSize) {
    std::vector<std::uint8_t> record(data, data + kSettingsRecordSize);
    fix_record_crc(record.data());
    check_record(record.data(), record.size());
  }
  if (size >= kSettingsSlotsBytes) {
    std::vector<std::uint8_t> image(data, data + size);
    for (std::size_t slot = 0; slot < kSlotCount; ++slot) fix_slot_crcs(image.data() + slot * kSlotSize);
    check_memory(std::move(image));
  }
  return 0;
}
