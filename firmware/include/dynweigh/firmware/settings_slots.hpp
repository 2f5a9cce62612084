#pragma once
// Settings that survive power loss: two slots in non-volatile memory, each one settings record
// (persistent_settings.hpp, unchanged, as the payload) behind a header with a sequence number and
// a CRC over header and payload. `load` takes the newest slot that is intact; `save` overwrites the
// other (older or damaged) one, so a write cut at any byte leaves the previous values readable.
//
// Slot layout, little-endian: magic u32 "DWSL", sequence u32, payload length u32,
// crc32 u32 (over sequence, length and payload), payload (kSettingsRecordSize bytes).
#include <cstddef>
#include <cstdint>

#include "dynweigh/firmware/persistent_settings.hpp"

namespace dynweigh::firmware {

// A byte-addressed non-volatile memory (EEPROM, a flash sector pair, a file). A board implements it;
// a write may be cut short by power loss at any byte.
class NvmBlock {
 public:
  virtual ~NvmBlock() = default;
  virtual std::size_t size() const = 0;
  virtual bool read(std::size_t offset, std::uint8_t* data, std::size_t length) const = 0;
  virtual bool write(std::size_t offset, const std::uint8_t* data, std::size_t length) = 0;
};

inline constexpr std::size_t kSlotHeaderSize = 16;
inline constexpr std::size_t kSlotSize = kSlotHeaderSize + kSettingsRecordSize;
inline constexpr std::size_t kSlotCount = 2;
inline constexpr std::size_t kSettingsSlotsBytes = kSlotCount * kSlotSize;

// Encodes one slot image; returns kSlotSize, or 0 if `capacity` is too small.
std::size_t encode_slot(const PersistentSettings& settings, std::uint32_t sequence, std::uint8_t* out,
                        std::size_t capacity);
// False (outputs untouched) unless the slot image is complete and intact.
bool decode_slot(const std::uint8_t* data, std::size_t length, PersistentSettings& settings,
                 std::uint32_t& sequence);

class SettingsSlots {
 public:
  explicit SettingsSlots(NvmBlock& nvm) : nvm_(nvm) {}

  // The newest intact slot's settings; false (settings untouched) when neither slot is intact.
  bool load(PersistentSettings& settings);
  // Writes the settings into the slot not holding the newest intact record, with the next
  // sequence number, and reads it back. False when the memory is too small or the write failed.
  bool save(const PersistentSettings& settings);

  // After load or save: the slot holding the newest record (or -1) and its sequence number.
  int newest_slot() const { return newest_; }
  std::uint32_t newest_sequence() const { return sequence_; }

 private:
  // Reads both slots; sets newest_ and sequence_; decodes the newest into `settings` if given.
  bool scan(PersistentSettings* settings);

  NvmBlock& nvm_;
  int newest_ = -1;
  std::uint32_t sequence_ = 0;
};

}  // namespace dynweigh::firmware
