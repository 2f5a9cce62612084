#pragma once
// --nvm FILE at start-up: refuse a path that cannot keep settings (one line, non-zero exit), warn
// about a file that holds no intact record (starting from defaults) or is truncated, and save the
// starting settings at once so a storage that cannot be written is found now, not at the first `cal`.
#include <memory>
#include <optional>
#include <string>

#include "dynweigh/firmware/persistent_settings.hpp"
#include "dynweigh/hal/host/file_settings_store.hpp"

namespace dynweigh::tools {

struct NvmStart {
  std::unique_ptr<hal::host::FileSettingsStore> store;  // null without --nvm
  std::optional<firmware::PersistentSettings> stored;   // the intact record FILE held, if any
  bool fresh = false;  // a new (or erased, or unreadable) file: the board starts from its defaults
};

// Throws std::runtime_error (one line) for a path that cannot be used. Warnings go to stderr.
NvmStart open_nvm(const std::string& path, bool reset);

// With a store and no record loaded: writes `settings` as the first record; throws if it cannot.
void save_starting_settings(NvmStart& nvm, const std::string& path, const firmware::PersistentSettings& settings);

}  // namespace dynweigh::tools
