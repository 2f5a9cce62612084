#include "dynweigh/hal/host/file_settings_store.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <vector>

namespace dynweigh::hal::host {
namespace {

std::runtime_error nvm_error(const std::string& path, const std::string& reason) {
  return std::runtime_error("--nvm " + path + ": " + reason);
}

bool all_erased(int fd) {
  std::vector<std::uint8_t> bytes(kNvmFileBytes);
  return ::pread(fd, bytes.data(), bytes.size(), 0) == ssize_t(bytes.size()) &&
         std::all_of(bytes.begin(), bytes.end(), [](std::uint8_t b) { return b == 0xFF; });
}

void erase(int fd, const std::string& path) {
  const std::vector<std::uint8_t> erased(kNvmFileBytes, 0xFF);
  if (::ftruncate(fd, 0) != 0 || ::pwrite(fd, erased.data(), erased.size(), 0) != ssize_t(erased.size()) ||
      ::fsync(fd) != 0) {
    const std::string reason = std::strerror(errno);
    ::close(fd);
    throw nvm_error(path, "cannot write: " + reason);
  }
}

// An older version's file, the settings alone: the logbook's part is added, erased.
void grow(int fd, const std::string& path, std::size_t from) {
  const std::vector<std::uint8_t> erased(kNvmFileBytes - from, 0xFF);
  if (::pwrite(fd, erased.data(), erased.size(), off_t(from)) != ssize_t(erased.size()) || ::fsync(fd) != 0) {
    const std::string reason = std::strerror(errno);
    ::close(fd);
    throw nvm_error(path, "cannot write: " + reason);
  }
}

// An older file's logbook (and totalizers, from version 6) moves to where this version keeps them
// (after the larger settings slots, which leaves the old slots where they were); what the older file
// lacks is added, erased.
void move_behind_settings(int fd, const std::string& path, std::size_t from, std::size_t length) {
  std::vector<std::uint8_t> moved(kNvmFileBytes - kFileLogbookOffset, 0xFF);
  if (::pread(fd, moved.data(), length, off_t(from)) != ssize_t(length) ||
      ::pwrite(fd, moved.data(), moved.size(), off_t(kFileLogbookOffset)) != ssize_t(moved.size()) || ::fsync(fd) != 0) {
    const std::string reason = std::strerror(errno);
    ::close(fd);
    throw nvm_error(path, "cannot write: " + reason);
  }
}

}  // namespace

NvmFile prepare_nvm_file(const std::string& path, bool reset) {
  struct stat st {};
  const bool exists = ::stat(path.c_str(), &st) == 0;
  if (exists && S_ISDIR(st.st_mode)) throw nvm_error(path, "is a directory, not a file");
  if (exists && !S_ISREG(st.st_mode)) throw nvm_error(path, "is not a regular file");
  const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) throw nvm_error(path, std::string(exists ? "cannot open for writing: " : "cannot create: ") + std::strerror(errno));
  NvmFile state = NvmFile::sized;
  if (!exists || reset) {
    erase(fd, path);
    state = exists ? NvmFile::erased : NvmFile::created;
  } else if (st.st_size == off_t(kSettingsOnlyFileBytes)) {
    grow(fd, path, std::size_t(st.st_size));
  } else if (st.st_size == off_t(kVersion5FileBytes)) {
    constexpr std::size_t kLogBytes = kFileLogbookSlots * firmware::kLogRecordSize;
    move_behind_settings(fd, path, kVersion5FileBytes - kLogBytes, kLogBytes);
  } else if (st.st_size == off_t(kVersion6FileBytes)) {
    move_behind_settings(fd, path, kVersion6SettingsBytes, kVersion6FileBytes - kVersion6SettingsBytes);
  } else if (st.st_size == off_t(kVersion7FileBytes)) {
    move_behind_settings(fd, path, kVersion7SettingsBytes, kVersion7FileBytes - kVersion7SettingsBytes);
  } else if (st.st_size == off_t(kVersion8FileBytes)) {
    move_behind_settings(fd, path, kVersion8SettingsBytes, kVersion8FileBytes - kVersion8SettingsBytes);
  } else if (st.st_size == off_t(kVersion9FileBytes)) {
    move_behind_settings(fd, path, kVersion9SettingsBytes, kVersion9FileBytes - kVersion9SettingsBytes);
  } else if (st.st_size != off_t(kNvmFileBytes)) {
    state = NvmFile::wrong_size;
  } else if (all_erased(fd)) {
    state = NvmFile::erased;
  }
  ::close(fd);
  return state;
}

bool FileNvm::read(std::size_t offset, std::uint8_t* data, std::size_t length) const {
  if (offset + length > size()) return false;
  std::fill(data, data + length, std::uint8_t(0xFF));
  const int fd = ::open(path_.c_str(), O_RDONLY);
  if (fd < 0) return true;  // no file yet: erased memory
  const ssize_t n = ::pread(fd, data, length, off_t(offset));
  ::close(fd);
  return n >= 0;  // a short file reads as erased beyond its end
}

bool FileNvm::write(std::size_t offset, const std::uint8_t* data, std::size_t length) {
  if (offset + length > size()) return false;
  const int fd = ::open(path_.c_str(), O_WRONLY | O_CREAT, 0644);
  if (fd < 0) return false;
  const bool written = ::pwrite(fd, data, length, off_t(offset)) == ssize_t(length) && ::fsync(fd) == 0;
  ::close(fd);
  return written;
}

}  // namespace dynweigh::hal::host
