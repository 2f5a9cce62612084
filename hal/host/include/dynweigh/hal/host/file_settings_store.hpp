#pragma once
// Non-volatile storage in a file (`dynweigh-fw --nvm FILE`). Written to a temporary file and
// renamed, so a crash mid-write leaves the previous record.
#include <string>

#include "dynweigh/hal/ports.hpp"

namespace dynweigh::hal::host {

class FileSettingsStore final : public SettingsStore {
 public:
  explicit FileSettingsStore(std::string path) : path_(std::move(path)) {}
  bool load(firmware::PersistentSettings& settings) override;
  bool save(const firmware::PersistentSettings& settings) override;

 private:
  std::string path_;
};

}  // namespace dynweigh::hal::host
