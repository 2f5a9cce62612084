// The logbook under power loss: a ring of CRC'd records with one slot always free. A write cut at
// any byte (EEPROM or flash, with or without a torn byte) loses at most the record being written;
// every record written before it reads back unchanged, and the next append carries on.
#include <gtest/gtest.h>

#include <optional>

#include "dynweigh/firmware/logbook.hpp"
#include "dynweigh/hal/host/cuttable_nvm.hpp"

namespace dynweigh {
namespace {

using firmware::Logbook;
using firmware::LogRecord;
using firmware::ToleranceVerdict;
using hal::host::CuttableNvm;

constexpr std::size_t kOffset = 100;  // the ring need not start at 0: settings come first
constexpr std::uint32_t kSlots = 5;

// Record number `n`: every field differs from the other records'.
LogRecord nth(std::uint32_t n) {
  LogRecord r;
  r.jiffy = 1000 * n + 7;
  r.target_dg = std::int32_t(20000 + n);
  r.final_dg = -std::int32_t(n) * 3;
  r.material = std::uint8_t(n % 16);
  r.tolerance = ToleranceVerdict(n % 5);
  r.topups = std::uint8_t(n % 4);
  return r;
}

void expect_record(const Logbook& book, std::uint32_t n) {
  LogRecord r;
  ASSERT_TRUE(book.read(n, r)) << "record " << n;
  const LogRecord want = nth(n);
  EXPECT_EQ(r.sequence, n);
  EXPECT_EQ(r.jiffy, want.jiffy);
  EXPECT_EQ(r.target_dg, want.target_dg);
  EXPECT_EQ(r.final_dg, want.final_dg);
  EXPECT_EQ(r.material, want.material);
  EXPECT_EQ(r.tolerance, want.tolerance);
  EXPECT_EQ(r.topups, want.topups);
}

std::uint32_t append_n(Logbook& book, std::uint32_t from, std::uint32_t to) {
  for (std::uint32_t n = from; n <= to; ++n) {
    LogRecord r = nth(n);
    EXPECT_TRUE(book.append(r));
    EXPECT_EQ(r.sequence, n);
  }
  return to;
}

TEST(Logbook, EmptyMemoryIsAnEmptyLogbook) {
  CuttableNvm nvm(kOffset + kSlots * firmware::kLogRecordSize);
  Logbook book(nvm, kOffset, kSlots);
  ASSERT_TRUE(book.open());
  EXPECT_EQ(book.last_sequence(), 0u);
  EXPECT_EQ(book.first_sequence(), 0u);
  LogRecord r;
  EXPECT_FALSE(book.read(1, r));
}

TEST(Logbook, KeepsTheNewestSlotsMinusOneAcrossARestart) {
  CuttableNvm nvm(kOffset + kSlots * firmware::kLogRecordSize);
  {
    Logbook book(nvm, kOffset, kSlots);
    ASSERT_TRUE(book.open());
    append_n(book, 1, 13);
  }
  Logbook book(nvm, kOffset, kSlots);
  ASSERT_TRUE(book.open());
  EXPECT_EQ(book.last_sequence(), 13u);
  EXPECT_EQ(book.first_sequence(), 13u - (kSlots - 1) + 1);
  for (std::uint32_t n = book.first_sequence(); n <= 13; ++n) expect_record(book, n);
  LogRecord r;
  EXPECT_FALSE(book.read(book.first_sequence() - 1, r)) << "dropped out of the ring";
  EXPECT_FALSE(book.read(14, r));
  for (std::size_t i = 0; i < kOffset; ++i) ASSERT_EQ(nvm.bytes()[i], 0xFF) << "wrote before its region";
}

TEST(Logbook, RefusesAMemoryTooSmallForTheRing) {
  CuttableNvm nvm(kOffset + kSlots * firmware::kLogRecordSize - 1);
  Logbook book(nvm, kOffset, kSlots);
  EXPECT_FALSE(book.open());
  LogRecord r = nth(1);
  EXPECT_FALSE(book.append(r));
}

TEST(Logbook, AFlippedBitLosesOnlyThatRecord) {
  CuttableNvm nvm(kOffset + kSlots * firmware::kLogRecordSize);
  Logbook writer(nvm, kOffset, kSlots);
  ASSERT_TRUE(writer.open());
  append_n(writer, 1, 4);
  nvm.bytes()[kOffset + 2 * firmware::kLogRecordSize + 13] ^= 0x10;  // record 3's target
  Logbook book(nvm, kOffset, kSlots);
  ASSERT_TRUE(book.open());
  EXPECT_EQ(book.last_sequence(), 4u);
  LogRecord r;
  EXPECT_FALSE(book.read(3, r));
  expect_record(book, 1);
  expect_record(book, 2);
  expect_record(book, 4);
}

// The write of record `k` cut after every byte, on both media, torn or not: records before `k`
// survive; `k` is there only if the cut came after its last differing byte; the next append works.
void cut_every_byte(std::uint32_t k, CuttableNvm::Medium medium, std::optional<std::uint8_t> torn) {
  for (std::size_t cut = 0; cut < firmware::kLogRecordSize; ++cut) {
    SCOPED_TRACE(::testing::Message() << "record " << k << " cut after " << cut << " bytes");
    CuttableNvm nvm(kOffset + kSlots * firmware::kLogRecordSize, medium);
    {
      Logbook book(nvm, kOffset, kSlots);
      ASSERT_TRUE(book.open());
      append_n(book, 1, k - 1);
      nvm.arm_cut(cut, torn);
      LogRecord r = nth(k);
      EXPECT_FALSE(book.append(r));
    }
    Logbook book(nvm, kOffset, kSlots);
    ASSERT_TRUE(book.open());
    ASSERT_GE(book.last_sequence(), k - 1);
    ASSERT_LE(book.last_sequence(), k);
    const std::uint32_t first_kept = k - 1 > kSlots - 1 ? k - 1 - (kSlots - 1) + 1 : 1;
    for (std::uint32_t n = first_kept; n < k; ++n) expect_record(book, n);
    if (book.last_sequence() == k) expect_record(book, k);
    LogRecord next = nth(book.last_sequence() + 1);
    ASSERT_TRUE(book.append(next));
    expect_record(book, next.sequence);
  }
}

TEST(Logbook, AWriteCutAtAnyByteLosesAtMostTheRecordBeingWritten) {
  for (auto medium : {CuttableNvm::Medium::eeprom, CuttableNvm::Medium::flash}) {
    for (auto torn : {std::optional<std::uint8_t>{}, std::optional<std::uint8_t>{0x5A}}) {
      cut_every_byte(1, medium, torn);                  // into an empty ring
      cut_every_byte(3, medium, torn);                  // before the ring is full
      cut_every_byte(kSlots + 4, medium, torn);         // over an evicted record
      cut_every_byte(3 * kSlots + 2, medium, torn);     // many times round
    }
  }
}

TEST(Logbook, ToleranceNamesAreTheConsoleWords) {
  EXPECT_STREQ(firmware::tolerance_verdict_name(ToleranceVerdict::ok), "ok");
  EXPECT_STREQ(firmware::tolerance_verdict_name(ToleranceVerdict::warn_low), "warn_low");
  EXPECT_STREQ(firmware::tolerance_verdict_name(ToleranceVerdict::warn_high), "warn_high");
  EXPECT_STREQ(firmware::tolerance_verdict_name(ToleranceVerdict::low), "low");
  EXPECT_STREQ(firmware::tolerance_verdict_name(ToleranceVerdict::high), "high");
}

}  // namespace
}  // namespace dynweigh
