#include "nvm_start.hpp"

#include <sys/stat.h>

#include <cstdio>
#include <stdexcept>

#include "dynweigh/firmware/settings_slots.hpp"

namespace dynweigh::tools {

using hal::host::NvmFile;

NvmStart open_nvm(const std::string& path, bool reset) {
  NvmStart nvm;
  if (path.empty()) return nvm;
  const NvmFile file = hal::host::prepare_nvm_file(path, reset);
  nvm.store = std::make_unique<hal::host::FileSettingsStore>(path);
  firmware::PersistentSettings settings;
  if (file != NvmFile::created && file != NvmFile::erased && nvm.store->load(settings)) nvm.stored = settings;
  nvm.fresh = !nvm.stored;
  struct stat st {};
  const long long bytes = ::stat(path.c_str(), &st) == 0 ? static_cast<long long>(st.st_size) : -1;
  const std::size_t expected = hal::host::kNvmFileBytes;
  if (file == NvmFile::wrong_size && nvm.stored) {
    std::fprintf(stderr,
                 "dynweigh-fw: warning: --nvm %s is %lld bytes, not %zu (%s): using the intact record it still "
                 "holds\n",
                 path.c_str(), bytes, expected,
                 bytes < static_cast<long long>(expected) ? "truncated" : "not a dynweigh settings file?");
  } else if ((file == NvmFile::wrong_size || file == NvmFile::sized) && !nvm.stored) {
    const char* what = bytes == 0                                          ? "empty"
                       : bytes < static_cast<long long>(expected) ? "truncated or corrupt"
                                                                          : "corrupt";
    std::fprintf(stderr,
                 "dynweigh-fw: warning: --nvm %s holds no intact settings record (%s): starting from defaults and "
                 "overwriting it (--nvm-reset does this without a warning)\n",
                 path.c_str(), what);
    hal::host::prepare_nvm_file(path, /*reset=*/true);  // a fresh memory of the right size
  }
  return nvm;
}

void save_starting_settings(NvmStart& nvm, const std::string& path, const firmware::PersistentSettings& settings) {
  if (!nvm.store || nvm.stored) return;
  if (!nvm.store->save(settings)) throw std::runtime_error("--nvm " + path + ": cannot write the settings");
}

}  // namespace dynweigh::tools
