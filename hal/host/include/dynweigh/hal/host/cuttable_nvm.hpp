#pragma once
// Host non-volatile memory that can lose power in the middle of a write: RAM bytes that start
// erased (0xFF), and a cut armed to stop the next write after a chosen number of bytes. What the
// cut leaves is configurable: the bytes after the cut untouched (EEPROM, byte-programmed), or the
// whole range erased first and only the bytes before the cut programmed (flash: erase, then
// program); the byte at the cut may be torn (a garbage value). Power-loss tests run against it.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "dynweigh/firmware/settings_slots.hpp"
#include "dynweigh/hal/ports.hpp"

namespace dynweigh::hal::host {

class CuttableNvm final : public firmware::NvmBlock {
 public:
  enum class Medium : std::uint8_t { eeprom, flash };

  explicit CuttableNvm(std::size_t size, Medium medium = Medium::eeprom)
      : bytes_(size, std::uint8_t(0xFF)), medium_(medium) {}

  std::size_t size() const override { return bytes_.size(); }
  bool read(std::size_t offset, std::uint8_t* data, std::size_t length) const override;
  // With a cut armed: programs the first `cut` bytes, tears the next one if asked, disarms the
  // cut and returns false (the board lost power: the write never completed).
  bool write(std::size_t offset, const std::uint8_t* data, std::size_t length) override;

  // The next write stops after `bytes_written` bytes; `torn_value`, if given, lands at the cut.
  void arm_cut(std::size_t bytes_written, std::optional<std::uint8_t> torn_value = std::nullopt) {
    cut_ = bytes_written;
    torn_ = torn_value;
  }
  bool cut_armed() const { return cut_.has_value(); }
  std::size_t writes() const { return writes_; }
  const std::vector<std::uint8_t>& bytes() const { return bytes_; }
  std::vector<std::uint8_t>& bytes() { return bytes_; }

 private:
  std::vector<std::uint8_t> bytes_;
  Medium medium_;
  std::optional<std::size_t> cut_;
  std::optional<std::uint8_t> torn_;
  std::size_t writes_ = 0;
};

// The SettingsStore port over two slots in an NvmBlock (the firmware's SettingsSlots).
class SlottedSettingsStore final : public SettingsStore {
 public:
  explicit SlottedSettingsStore(firmware::NvmBlock& nvm) : slots_(nvm) {}
  bool load(firmware::PersistentSettings& settings) override { return slots_.load(settings); }
  bool save(const firmware::PersistentSettings& settings) override { return slots_.save(settings); }
  const firmware::SettingsSlots& slots() const { return slots_; }

 private:
  firmware::SettingsSlots slots_;
};

}  // namespace dynweigh::hal::host
