#include "dynweigh/firmware/settings_slots.hpp"

#include "dynweigh/firmware/little_endian.hpp"

namespace dynweigh::firmware {
namespace {

constexpr std::uint32_t kSlotMagic = 0x4C535744;  // "DWSL"

// The records of older firmware (versions 9, 8, 7, 6, 5 and 4), and where their second slot lay: a
// board updated from one still finds its settings (the next save writes today's layout).
constexpr std::size_t kOlderRecordSizes[] = {kSettingsRecordSizeV9, kSettingsRecordSizeV8, kSettingsRecordSizeV7, kSettingsRecordSizeV6,
                                             kSettingsRecordSizeV5, kSettingsRecordSizeV4};

bool known_record_size(std::size_t payload) {
  if (payload == kSettingsRecordSize) return true;
  for (std::size_t size : kOlderRecordSizes) {
    if (payload == size) return true;
  }
  return false;
}

std::uint32_t slot_crc(const std::uint8_t* slot, std::size_t payload) {
  // Over sequence and length (bytes 4..11) and the payload.
  return crc32(slot + 4, 8) ^ crc32(slot + kSlotHeaderSize, payload);
}
// Serial-number order (RFC 1982): `a` is newer than `b` even across the wrap of the counter.
bool newer(std::uint32_t a, std::uint32_t b) { return std::int32_t(a - b) > 0; }

}  // namespace

std::size_t encode_slot(const PersistentSettings& settings, std::uint32_t sequence, std::uint8_t* out,
                        std::size_t capacity) {
  if (capacity < kSlotSize) return 0;
  if (encode_settings(settings, out + kSlotHeaderSize, capacity - kSlotHeaderSize) != kSettingsRecordSize) {
    return 0;
  }
  put_u32(out, kSlotMagic);
  put_u32(out + 4, sequence);
  put_u32(out + 8, std::uint32_t(kSettingsRecordSize));
  put_u32(out + 12, slot_crc(out, kSettingsRecordSize));
  return kSlotSize;
}

bool decode_slot(const std::uint8_t* data, std::size_t length, PersistentSettings& settings,
                 std::uint32_t& sequence) {
  if (length < kSlotHeaderSize || get_u32(data) != kSlotMagic) return false;
  const std::size_t payload = get_u32(data + 8);
  if (!known_record_size(payload)) return false;
  if (length < kSlotHeaderSize + payload || get_u32(data + 12) != slot_crc(data, payload)) return false;
  PersistentSettings decoded;
  if (!decode_settings(data + kSlotHeaderSize, payload, decoded)) return false;
  settings = decoded;
  sequence = get_u32(data + 4);
  return true;
}

bool SettingsSlots::scan(PersistentSettings* settings) {
  newest_ = -1;
  sequence_ = 0;
  if (nvm_.size() < kSettingsSlotsBytes) return false;
  PersistentSettings newest_settings;
  for (std::size_t slot = 0; slot < kSlotCount; ++slot) {
    std::uint8_t image[kSlotSize];
    PersistentSettings decoded;
    std::uint32_t sequence = 0;
    bool found = nvm_.read(slot * kSlotSize, image, kSlotSize) && decode_slot(image, kSlotSize, decoded, sequence);
    for (std::size_t older : kOlderRecordSizes) {
      const std::size_t older_slot = kSlotHeaderSize + older;
      found = found || (nvm_.read(slot * older_slot, image, older_slot) && decode_slot(image, older_slot, decoded, sequence));
    }
    if (!found) continue;
    if (newest_ < 0 || newer(sequence, sequence_)) {
      newest_ = int(slot);
      sequence_ = sequence;
      newest_settings = decoded;
    }
  }
  if (newest_ < 0) return false;
  if (settings) *settings = newest_settings;
  return true;
}

bool SettingsSlots::load(PersistentSettings& settings) { return scan(&settings); }

bool SettingsSlots::save(const PersistentSettings& settings) {
  if (nvm_.size() < kSettingsSlotsBytes) return false;
  const bool any = scan(nullptr);
  const std::size_t target = any ? std::size_t(1 - newest_) : 0;
  const std::uint32_t sequence = any ? sequence_ + 1 : 1;
  std::uint8_t image[kSlotSize];
  if (encode_slot(settings, sequence, image, sizeof image) != kSlotSize) return false;
  if (!nvm_.write(target * kSlotSize, image, kSlotSize)) return false;
  std::uint8_t back[kSlotSize];
  if (!nvm_.read(target * kSlotSize, back, kSlotSize)) return false;
  for (std::size_t i = 0; i < kSlotSize; ++i) {
    if (back[i] != image[i]) return false;
  }
  newest_ = int(target);
  sequence_ = sequence;
  return true;
}

}  // namespace dynweigh::firmware
