#include "dynweigh/hal/host/cuttable_nvm.hpp"

#include <algorithm>

namespace dynweigh::hal::host {

bool CuttableNvm::read(std::size_t offset, std::uint8_t* data, std::size_t length) const {
  if (offset > bytes_.size() || length > bytes_.size() - offset) return false;
  std::copy_n(bytes_.begin() + std::ptrdiff_t(offset), length, data);
  return true;
}

bool CuttableNvm::write(std::size_t offset, const std::uint8_t* data, std::size_t length) {
  if (offset > bytes_.size() || length > bytes_.size() - offset) return false;
  ++writes_;
  if (medium_ == Medium::flash) std::fill_n(bytes_.begin() + std::ptrdiff_t(offset), length, std::uint8_t(0xFF));
  const std::size_t programmed = cut_ ? std::min(*cut_, length) : length;
  std::copy_n(data, programmed, bytes_.begin() + std::ptrdiff_t(offset));
  if (!cut_) return true;
  if (torn_ && programmed < length) bytes_[offset + programmed] = *torn_;
  cut_.reset();
  torn_.reset();
  return programmed == length;
}

}  // namespace dynweigh::hal::host
