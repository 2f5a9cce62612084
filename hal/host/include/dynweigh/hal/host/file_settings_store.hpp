#pragma once
// Non-volatile storage in a file (`dynweigh-fw --nvm FILE`): the two-slot layout of
// firmware/settings_slots.hpp written in place, as a board writes its EEPROM, so a crash or power cut
// mid-write leaves the previous record readable.
#include <string>

#include "dynweigh/firmware/settings_slots.hpp"
#include "dynweigh/hal/ports.hpp"

namespace dynweigh::hal::host {

// The file as a byte-addressed memory of kSettingsSlotsBytes; bytes never written read as erased (0xFF).
class FileNvm final : public firmware::NvmBlock {
 public:
  explicit FileNvm(std::string path) : path_(std::move(path)) {}
  std::size_t size() const override { return firmware::kSettingsSlotsBytes; }
  bool read(std::size_t offset, std::uint8_t* data, std::size_t length) const override;
  bool write(std::size_t offset, const std::uint8_t* data, std::size_t length) override;

 private:
  std::string path_;
};

class FileSettingsStore final : public SettingsStore {
 public:
  explicit FileSettingsStore(std::string path) : nvm_(std::move(path)), slots_(nvm_) {}
  bool load(firmware::PersistentSettings& settings) override { return slots_.load(settings); }
  bool save(const firmware::PersistentSettings& settings) override { return slots_.save(settings); }

 private:
  FileNvm nvm_;
  firmware::SettingsSlots slots_;
};

}  // namespace dynweigh::hal::host
