#pragma once
// Non-volatile storage in a file (`dynweigh-fw --nvm FILE`): the two-slot layout of
// firmware/settings_slots.hpp written in place, as a board writes its EEPROM, so a crash or power cut
// mid-write leaves the previous record readable.
#include <string>

#include "dynweigh/firmware/settings_slots.hpp"
#include "dynweigh/firmware/totalizers.hpp"
#include "dynweigh/hal/ports.hpp"

namespace dynweigh::hal::host {

// The file: the two settings slots, then the logbook's ring of kFileLogbookSlots records (one
// fewer kept), then the materials' totalizers' two slots. A file of an older version is grown: the
// settings alone (kSettingsOnlyFileBytes), version-5 settings and the logbook (kVersion5FileBytes), or
// version-6 to version-9 settings, the logbook and the totalizers (kVersion6FileBytes to
// kVersion9FileBytes), whose logbook and totalizers are moved behind today's larger settings slots;
// its settings load as they are.
inline constexpr std::size_t kFileLogbookSlots = 1001;
inline constexpr std::size_t kFileLogbookOffset = firmware::kSettingsSlotsBytes;
inline constexpr std::size_t kFileTotalizersOffset = kFileLogbookOffset + kFileLogbookSlots * firmware::kLogRecordSize;
inline constexpr std::size_t kNvmFileBytes = kFileTotalizersOffset + firmware::kTotalizerSlotsBytes;
inline constexpr std::size_t kSettingsOnlyFileBytes = 872;
inline constexpr std::size_t kVersion5FileBytes =
    firmware::kSlotCount * (firmware::kSlotHeaderSize + firmware::kSettingsRecordSizeV5) +
    kFileLogbookSlots * firmware::kLogRecordSize;
inline constexpr std::size_t kVersion6SettingsBytes =
    firmware::kSlotCount * (firmware::kSlotHeaderSize + firmware::kSettingsRecordSizeV6);
inline constexpr std::size_t kVersion6FileBytes = kVersion6SettingsBytes + kNvmFileBytes - kFileLogbookOffset;
inline constexpr std::size_t kVersion7SettingsBytes =
    firmware::kSlotCount * (firmware::kSlotHeaderSize + firmware::kSettingsRecordSizeV7);
inline constexpr std::size_t kVersion7FileBytes = kVersion7SettingsBytes + kNvmFileBytes - kFileLogbookOffset;
inline constexpr std::size_t kVersion8SettingsBytes =
    firmware::kSlotCount * (firmware::kSlotHeaderSize + firmware::kSettingsRecordSizeV8);
inline constexpr std::size_t kVersion8FileBytes = kVersion8SettingsBytes + kNvmFileBytes - kFileLogbookOffset;
inline constexpr std::size_t kVersion9SettingsBytes =
    firmware::kSlotCount * (firmware::kSlotHeaderSize + firmware::kSettingsRecordSizeV9);
inline constexpr std::size_t kVersion9FileBytes = kVersion9SettingsBytes + kNvmFileBytes - kFileLogbookOffset;

// The file as a byte-addressed memory of kNvmFileBytes; bytes never written read as erased (0xFF).
class FileNvm final : public firmware::NvmBlock {
 public:
  explicit FileNvm(std::string path) : path_(std::move(path)) {}
  std::size_t size() const override { return kNvmFileBytes; }
  bool read(std::size_t offset, std::uint8_t* data, std::size_t length) const override;
  bool write(std::size_t offset, const std::uint8_t* data, std::size_t length) override;

 private:
  std::string path_;
};

// What a --nvm file was when the board started, after prepare_nvm_file.
enum class NvmFile {
  created,     // there was none: made now, erased (0xFF) at its full size, as a new board's EEPROM
  erased,      // full size and never written (or reset with --nvm-reset): a new board
  sized,       // full size, written before: load() tells whether a record is intact
  wrong_size,  // shorter (truncated) or longer than kNvmFileBytes: damaged, or not ours
};

// Checks that `path` can keep the settings: an existing regular file the board can read and write,
// or a new one it can create (created now). `reset` erases what the file holds. Throws
// std::runtime_error with one line naming the path and the reason (a directory, a missing folder,
// no permission, not a regular file).
NvmFile prepare_nvm_file(const std::string& path, bool reset);

class FileSettingsStore final : public SettingsStore {
 public:
  explicit FileSettingsStore(std::string path) : nvm_(std::move(path)), slots_(nvm_) { logbook_.open(); }
  bool load(firmware::PersistentSettings& settings) override { return slots_.load(settings); }
  bool save(const firmware::PersistentSettings& settings) override { return slots_.save(settings); }
  firmware::Logbook* logbook() override { return &logbook_; }
  firmware::TotalizerSlots* totalizers() override { return &totalizers_; }

 private:
  FileNvm nvm_;
  firmware::SettingsSlots slots_;
  firmware::Logbook logbook_{nvm_, kFileLogbookOffset, kFileLogbookSlots};
  firmware::TotalizerSlots totalizers_{nvm_, kFileTotalizersOffset};
};

}  // namespace dynweigh::hal::host
