#include "dynweigh/firmware/logbook.hpp"

#include "dynweigh/firmware/little_endian.hpp"

#include "dynweigh/firmware/persistent_settings.hpp"

namespace dynweigh::firmware {
namespace {

constexpr std::uint32_t kLogMagic = 0x474C5744;  // "DWLG"
constexpr std::size_t kCrcOffset = kLogRecordSize - 4;


}  // namespace

void encode_log_record(const LogRecord& record, std::uint8_t* out) {
  put_u32(out, kLogMagic);
  put_u32(out + 4, record.sequence);
  put_u32(out + 8, record.jiffy);
  put_u32(out + 12, std::uint32_t(record.target_dg));
  put_u32(out + 16, std::uint32_t(record.final_dg));
  out[20] = record.material;
  out[21] = std::uint8_t(record.tolerance);
  out[22] = record.topups;
  out[23] = 0;
  put_u32(out + 24, 0);
  put_u32(out + kCrcOffset, crc32(out, kCrcOffset));
}

bool decode_log_record(const std::uint8_t* data, LogRecord& record) {
  if (get_u32(data) != kLogMagic || get_u32(data + kCrcOffset) != crc32(data, kCrcOffset)) return false;
  if (data[21] > std::uint8_t(ToleranceVerdict::high) || get_u32(data + 4) == 0) return false;
  record.sequence = get_u32(data + 4);
  record.jiffy = get_u32(data + 8);
  record.target_dg = std::int32_t(get_u32(data + 12));
  record.final_dg = std::int32_t(get_u32(data + 16));
  record.material = data[20];
  record.tolerance = ToleranceVerdict(data[21]);
  record.topups = data[22];
  return true;
}

bool Logbook::open() {
  last_ = 0;
  usable_ = slots_ >= 2 && offset_ + slots_ * kLogRecordSize <= nvm_.size();
  if (!usable_) return false;
  for (std::size_t slot = 0; slot < slots_; ++slot) {
    std::uint8_t image[kLogRecordSize];
    LogRecord record;
    if (!nvm_.read(offset_ + slot * kLogRecordSize, image, kLogRecordSize)) continue;
    if (!decode_log_record(image, record)) continue;
    // A record in a slot its sequence does not map to is not part of this ring (another layout).
    if (slot_offset(record.sequence) != offset_ + slot * kLogRecordSize) continue;
    if (record.sequence > last_) last_ = record.sequence;
  }
  return true;
}

bool Logbook::append(LogRecord& record) {
  if (!usable_) return false;
  record.sequence = last_ + 1;
  std::uint8_t image[kLogRecordSize];
  encode_log_record(record, image);
  const std::size_t at = slot_offset(record.sequence);
  if (!nvm_.write(at, image, kLogRecordSize)) return false;
  std::uint8_t back[kLogRecordSize];
  if (!nvm_.read(at, back, kLogRecordSize)) return false;
  for (std::size_t i = 0; i < kLogRecordSize; ++i) {
    if (back[i] != image[i]) return false;
  }
  last_ = record.sequence;
  return true;
}

std::uint32_t Logbook::first_sequence() const {
  if (last_ == 0) return 0;
  const auto kept = std::uint32_t(capacity());
  return last_ > kept ? last_ - kept + 1 : 1;
}

bool Logbook::read(std::uint32_t sequence, LogRecord& record) const {
  if (!usable_ || sequence == 0 || sequence < first_sequence() || sequence > last_) return false;
  std::uint8_t image[kLogRecordSize];
  LogRecord decoded;
  if (!nvm_.read(slot_offset(sequence), image, kLogRecordSize)) return false;
  if (!decode_log_record(image, decoded) || decoded.sequence != sequence) return false;
  record = decoded;
  return true;
}

}  // namespace dynweigh::firmware
