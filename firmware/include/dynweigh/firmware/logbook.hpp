#pragma once
// The logbook (alibi memory): every certified result, kept in non-volatile memory so a disputed
// fill can be looked up later. A ring of fixed-size records, each with its own sequence number and
// CRC. One slot of the ring is always left free: a new record goes into the slot whose record has
// already dropped out of the kept window, so a write cut by power loss at any byte loses at most
// the record being written, never one written before it.
//
// Record layout (kLogRecordSize bytes, little-endian): magic u32 "DWLG", sequence u32, jiffy u32,
// target (0.1 g) i32, final (0.1 g) i32, material u8, tolerance u8, top-ups u8, flags u8,
// reserved u32 (0), crc32 u32 over the 28 bytes before it.
#include <cstddef>
#include <cstdint>

#include "dynweigh/firmware/settings_slots.hpp"
#include "dynweigh/firmware/tolerance.hpp"

namespace dynweigh::firmware {

struct LogRecord {
  std::uint32_t sequence = 0;  // assigned by Logbook::append, 1 for the first record ever
  std::uint32_t jiffy = 0;     // the indicator's jiffy count when the result was certified
  std::int32_t target_dg = 0;  // 0.1 g
  std::int32_t final_dg = 0;   // 0.1 g
  std::uint8_t material = 0;
  ToleranceVerdict tolerance = ToleranceVerdict::ok;
  std::uint8_t topups = 0;
};

inline constexpr std::size_t kLogRecordSize = 32;

// Encodes `record` into `out` (kLogRecordSize bytes).
void encode_log_record(const LogRecord& record, std::uint8_t* out);
// False (record untouched) unless the bytes hold an intact record.
bool decode_log_record(const std::uint8_t* data, LogRecord& record);

class Logbook {
 public:
  // The ring occupies `slots` records from `offset` in `nvm`; it keeps slots - 1 of them.
  Logbook(NvmBlock& nvm, std::size_t offset, std::size_t slots) : nvm_(nvm), offset_(offset), slots_(slots) {}

  // Finds the newest intact record; false when the memory cannot hold the ring (the logbook then
  // refuses appends). An empty ring is not an error.
  bool open();
  // Writes `record` with the next sequence number (stored back into it) and reads it back.
  bool append(LogRecord& record);
  // The record with `sequence`, if it is still kept and intact.
  bool read(std::uint32_t sequence, LogRecord& record) const;

  bool usable() const { return usable_; }
  std::size_t capacity() const { return slots_ > 0 ? slots_ - 1 : 0; }
  // 0 when empty. Records first_sequence()..last_sequence() are the ones kept (a damaged one among
  // them, e.g. after a memory fault, reads false).
  std::uint32_t last_sequence() const { return last_; }
  std::uint32_t first_sequence() const;

 private:
  std::size_t slot_offset(std::uint32_t sequence) const {
    return offset_ + std::size_t((sequence - 1u) % std::uint32_t(slots_)) * kLogRecordSize;
  }

  NvmBlock& nvm_;
  std::size_t offset_;
  std::size_t slots_;
  bool usable_ = false;
  std::uint32_t last_ = 0;
};

}  // namespace dynweigh::firmware
