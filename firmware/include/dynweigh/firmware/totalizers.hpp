#pragma once
// The totalizers beside the statistics, one set per material: mass delivered, fills, valve and gate
// cycles and time dosing, counted since the last `stats reset` of that material. They are kept
// power-safe in a slot pair of their own (TotalizerSlots), written with each certified result:
// the settings record is too large to write every fill, and its save would hold each dose's OK.
// What a dose counted before a power cut that came before its result is lost with it.
//
// Slot layout, little-endian: magic u32 "DWTZ", sequence u32, payload length u32, crc32 u32 (over
// sequence, length and payload), then per material: total grams u64, fills u32, valve cycles u32,
// gate cycles u32, dosing jiffies u32, the logbook sequence the statistics start after u32.
#include <cstddef>
#include <cstdint>

#include "dynweigh/firmware/io.hpp"
#include "dynweigh/firmware/material_table.hpp"
#include "dynweigh/firmware/settings_slots.hpp"

namespace dynweigh::firmware {

struct Totalizers {
  std::uint64_t total_g = 0;         // the certified results' final weights
  std::uint32_t fills = 0;           // certified results
  std::uint32_t valve_cycles = 0;    // the dosing valve opened from closed
  std::uint32_t gate_cycles = 0;     // the discharge gate opened from closed
  std::uint32_t dosing_jiffies = 0;  // a dose or a top-up running
  std::uint32_t after_sequence = 0;  // the statistics read logbook records after this one

  void jiffy(ValveCommand before, ValveCommand now, bool dosing) {
    if (before == ValveCommand::closed && now != ValveCommand::closed) ++valve_cycles;
    if (dosing) ++dosing_jiffies;
  }
};

struct MaterialTotals {
  Totalizers material[MaterialTable::kMaterials];
};

inline constexpr std::size_t kTotalizerEntryBytes = 28;
inline constexpr std::size_t kTotalizerSlotSize = 16 + kTotalizerEntryBytes * MaterialTable::kMaterials;
inline constexpr std::size_t kTotalizerSlotsBytes = 2 * kTotalizerSlotSize;

// Two slots from `offset` in `nvm`: `save` overwrites the one not holding the newest intact record,
// so a write cut at any byte leaves the totals of the result before.
class TotalizerSlots {
 public:
  TotalizerSlots(NvmBlock& nvm, std::size_t offset) : nvm_(nvm), offset_(offset) {}
  // The newest intact slot's totals; false (totals untouched) when neither is intact.
  bool load(MaterialTotals& totals);
  bool save(const MaterialTotals& totals);

 private:
  bool scan(MaterialTotals* totals);

  NvmBlock& nvm_;
  std::size_t offset_;
  int newest_ = -1;
  std::uint32_t sequence_ = 0;
};

}  // namespace dynweigh::firmware
