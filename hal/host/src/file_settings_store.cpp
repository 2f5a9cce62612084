#include "dynweigh/hal/host/file_settings_store.hpp"

#include <cstdio>
#include <fstream>
#include <iterator>
#include <vector>

namespace dynweigh::hal::host {

bool FileSettingsStore::load(firmware::PersistentSettings& settings) {
  std::ifstream in(path_, std::ios::binary);
  if (!in) return false;
  std::vector<std::uint8_t> bytes;
  char c;
  while (bytes.size() <= 4 * firmware::kSettingsRecordSize && in.get(c)) bytes.push_back(std::uint8_t(c));
  return firmware::decode_settings(bytes.data(), bytes.size(), settings);
}

bool FileSettingsStore::save(const firmware::PersistentSettings& settings) {
  std::uint8_t record[firmware::kSettingsRecordSize];
  const std::size_t size = firmware::encode_settings(settings, record, sizeof record);
  const std::string temporary = path_ + ".tmp";
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out.write(reinterpret_cast<const char*>(record), std::streamsize(size))) return false;
  }
  return std::rename(temporary.c_str(), path_.c_str()) == 0;
}

}  // namespace dynweigh::hal::host
