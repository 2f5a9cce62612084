// Writes the settings fuzzer's seed corpus with the firmware's own encoder, so the seeds follow the
// record format: `fuzz_settings_seeds fuzz/corpus/settings` (regenerate after a format change).
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "dynweigh/firmware/learning_table.hpp"
#include "dynweigh/firmware/settings_slots.hpp"

namespace {

using namespace dynweigh::firmware;

PersistentSettings calibrated_and_learned() {
  PersistentSettings s;
  s.calibration = {200000, 0.25f, 20.0f, true, true};
  s.parameters.set(ParameterId::filter_hz, 5.0f);
  s.learning.learn(make_learning_key(5000.0f, 1.1f, 3.5f), 12.0f);
  s.learning.learn(make_learning_key(20000.0f, 0.9f, 3.5f), -30.0f);
  TopUpPulseLearning pulses;
  pulses.full = {{2400.0f, 60.0f, 40000.0f, -900.0f, 300.0f, 3}, 2500.0f, 0.08f, 3};
  s.materials.keep_pulses(pulses);
  return s;
}

std::vector<std::uint8_t> two_slots(const PersistentSettings& a, std::uint32_t sequence_a, const PersistentSettings& b,
                                    std::uint32_t sequence_b) {
  std::vector<std::uint8_t> image(kSettingsSlotsBytes, 0xFF);  // erased flash
  encode_slot(a, sequence_a, image.data(), kSlotSize);
  encode_slot(b, sequence_b, image.data() + kSlotSize, kSlotSize);
  return image;
}

bool write(const std::string& path, const std::vector<std::uint8_t>& bytes) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return false;
  const bool ok = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
  return std::fclose(f) == 0 && ok;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: fuzz_settings_seeds OUT_DIR\n");
    return 2;
  }
  const std::string dir = argv[1];
  const PersistentSettings factory;
  const PersistentSettings learned = calibrated_and_learned();

  std::vector<std::uint8_t> blank_b = two_slots(learned, 1, factory, 0);
  for (std::size_t i = kSlotSize; i < kSettingsSlotsBytes; ++i) blank_b[i] = 0xFF;
  std::vector<std::uint8_t> torn = two_slots(learned, 7, factory, 8);
  for (std::size_t i = kSlotSize + kSlotSize / 2; i < kSettingsSlotsBytes; ++i) torn[i] = 0xFF;  // cut mid-write
  std::vector<std::uint8_t> record(kSettingsRecordSize);
  encode_settings(learned, record.data(), record.size());

  const bool ok = write(dir + "/two_slots", two_slots(factory, 1, learned, 2)) &&
                  write(dir + "/sequence_wrap", two_slots(learned, 0xFFFFFFFFu, factory, 0)) &&
                  write(dir + "/one_slot", blank_b) && write(dir + "/torn_write", torn) &&
                  write(dir + "/bare_record", record) &&
                  write(dir + "/erased", std::vector<std::uint8_t>(kSettingsSlotsBytes, 0xFF));
  if (!ok) {
    std::fprintf(stderr, "cannot write the seeds into %s\n", dir.c_str());
    return 1;
  }
  return 0;
}
