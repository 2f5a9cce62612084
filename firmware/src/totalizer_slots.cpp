#include "dynweigh/firmware/little_endian.hpp"
#include "dynweigh/firmware/totalizers.hpp"

namespace dynweigh::firmware {
namespace {

constexpr std::uint32_t kTotalizerMagic = 0x5A545744;  // "DWTZ"
constexpr std::size_t kPayload = kTotalizerSlotSize - 16;

std::uint32_t slot_crc(const std::uint8_t* slot) { return crc32(slot + 4, 8) ^ crc32(slot + 16, kPayload); }
bool newer(std::uint32_t a, std::uint32_t b) { return std::int32_t(a - b) > 0; }

void encode(const MaterialTotals& totals, std::uint32_t sequence, std::uint8_t* out) {
  put_u32(out, kTotalizerMagic);
  put_u32(out + 4, sequence);
  put_u32(out + 8, std::uint32_t(kPayload));
  for (std::size_t n = 0; n < MaterialTable::kMaterials; ++n) {
    const Totalizers& t = totals.material[n];
    std::uint8_t* p = out + 16 + kTotalizerEntryBytes * n;
    put_u32(p, std::uint32_t(t.total_g));
    put_u32(p + 4, std::uint32_t(t.total_g >> 32));
    put_u32(p + 8, t.fills);
    put_u32(p + 12, t.valve_cycles);
    put_u32(p + 16, t.gate_cycles);
    put_u32(p + 20, t.dosing_jiffies);
    put_u32(p + 24, t.after_sequence);
  }
  put_u32(out + 12, slot_crc(out));
}

bool decode(const std::uint8_t* in, MaterialTotals& totals, std::uint32_t& sequence) {
  if (get_u32(in) != kTotalizerMagic || get_u32(in + 8) != kPayload || get_u32(in + 12) != slot_crc(in)) return false;
  sequence = get_u32(in + 4);
  for (std::size_t n = 0; n < MaterialTable::kMaterials; ++n) {
    Totalizers& t = totals.material[n];
    const std::uint8_t* p = in + 16 + kTotalizerEntryBytes * n;
    t.total_g = std::uint64_t(get_u32(p)) | (std::uint64_t(get_u32(p + 4)) << 32);
    t.fills = get_u32(p + 8);
    t.valve_cycles = get_u32(p + 12);
    t.gate_cycles = get_u32(p + 16);
    t.dosing_jiffies = get_u32(p + 20);
    t.after_sequence = get_u32(p + 24);
  }
  return true;
}

}  // namespace

bool TotalizerSlots::scan(MaterialTotals* totals) {
  newest_ = -1;
  sequence_ = 0;
  if (nvm_.size() < offset_ + kTotalizerSlotsBytes) return false;
  for (std::size_t slot = 0; slot < 2; ++slot) {
    std::uint8_t image[kTotalizerSlotSize];
    MaterialTotals decoded;
    std::uint32_t sequence = 0;
    if (!nvm_.read(offset_ + slot * kTotalizerSlotSize, image, kTotalizerSlotSize) || !decode(image, decoded, sequence)) {
      continue;
    }
    if (newest_ >= 0 && !newer(sequence, sequence_)) continue;
    newest_ = int(slot);
    sequence_ = sequence;
    if (totals) *totals = decoded;
  }
  return newest_ >= 0;
}

bool TotalizerSlots::load(MaterialTotals& totals) { return scan(&totals); }

bool TotalizerSlots::save(const MaterialTotals& totals) {
  if (nvm_.size() < offset_ + kTotalizerSlotsBytes) return false;
  if (newest_ < 0) scan(nullptr);
  const std::size_t target = newest_ >= 0 ? std::size_t(1 - newest_) : 0;
  const std::uint32_t sequence = newest_ >= 0 ? sequence_ + 1 : 1;
  std::uint8_t image[kTotalizerSlotSize];
  encode(totals, sequence, image);
  const std::size_t at = offset_ + target * kTotalizerSlotSize;
  if (!nvm_.write(at, image, kTotalizerSlotSize)) return false;
  std::uint8_t back[kTotalizerSlotSize];
  if (!nvm_.read(at, back, kTotalizerSlotSize)) return false;
  for (std::size_t i = 0; i < kTotalizerSlotSize; ++i) {
    if (back[i] != image[i]) return false;
  }
  newest_ = int(target);
  sequence_ = sequence;
  return true;
}

}  // namespace dynweigh::firmware
