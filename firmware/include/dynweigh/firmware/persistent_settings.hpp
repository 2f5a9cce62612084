#pragma once
// What survives a restart: calibration and parameters, as one fixed-size record with a magic,
// a version and a CRC so a blank or damaged store is recognised and never half-trusted.
#include <cstddef>
#include <cstdint>

#include "dynweigh/firmware/baseline_learning.hpp"
#include "dynweigh/firmware/learning_table.hpp"
#include "dynweigh/firmware/material_table.hpp"
#include "dynweigh/firmware/parameters.hpp"

namespace dynweigh::firmware {

// The zero is kept as whole counts and a part of one: a float alone would lose whole counts at an
// offset of a few million, and a load cell's offset can lie anywhere in the ADC's int32 range.
struct Calibration {
  std::int32_t zero_counts = 0;  // counts of the empty scale, whole
  float zero_fraction = 0.0f;    // and the part of a count the average adds, in [0, 1)
  float counts_per_gram = 0.0f;  // span
  bool zero_set = false;
  bool span_set = false;
  bool valid() const { return zero_set && span_set && counts_per_gram > 0.0f; }
  // `raw` minus the zero, in counts.
  float counts_above_zero(std::int32_t raw) const {
    return float(std::int64_t(raw) - zero_counts) - zero_fraction;
  }
};

struct PersistentSettings {
  Calibration calibration;
  Parameters parameters;
  LearningTable learning;
  BaselineLearning baselines;
  MaterialTable materials;
};

inline constexpr std::size_t kLearningEntryBytes = 12;
// A learned least-squares law: theta1, theta2, p11, p12, p22 (f32 each), fills u16, 2 bytes pad.
inline constexpr std::size_t kRlsStateBytes = 24;
// pac: spill law, blind law; flowpreact: lag f32, fills u16, pad, blind law.
inline constexpr std::size_t kBaselineLearningBytes = 2 * kRlsStateBytes + 8 + kRlsStateBytes;
// The material table: selected u8, 3 bytes pad, then each material: defined u8, 3 bytes pad, name
// 16 bytes (NUL-padded), density f32, class f32; from version 7 on, what the model's fills of it
// measured: the open-time law, the measured close's let-through f32, its fills u16, and how far the
// measured closes came out from their predictions (measured_close_spread.hpp; a record before this
// firmware has zeros there: nothing learned): the root of their mean square in 1/64 sigma u8, their
// number u8;
// from version 8 on, what its top-up pulses taught: for full open, then half open, the law (as the
// open-time law), the prior flow and the travel (f32 each), the pulses u8, 3 bytes pad; from version
// 9 on, the longest open time the open-time law was taught at f32, and the valve's timing its doses
// measured: dead time f32, travel f32, dead-time doses u16, strokes u16; from version 10 on, its
// last doses that ran full open (dose_history.hpp): count u8, next u8, the slowest dead time the
// valve's feedback showed on its doses (0.1 ms) u16 (0: none; a record before this firmware has
// zeros there), then 8 doses of open time (0.1 ms) u16 and final (g) u16.
inline constexpr std::size_t kMaterialEntryBytesV6 = 4 + Material::kNameBytes + 4 + 4;
inline constexpr std::size_t kMaterialLearningBytes = kRlsStateBytes + 8;
inline constexpr std::size_t kMaterialEntryBytesV7 = kMaterialEntryBytesV6 + kMaterialLearningBytes;
inline constexpr std::size_t kPulseLawLearningBytes = kRlsStateBytes + 4 + 4 + 4;
inline constexpr std::size_t kMaterialEntryBytesV8 = kMaterialEntryBytesV7 + 2 * kPulseLawLearningBytes;
inline constexpr std::size_t kValveTimingLearningBytes = 4 + 4 + 2 + 2;
inline constexpr std::size_t kMaterialEntryBytesV9 = kMaterialEntryBytesV8 + 4 + kValveTimingLearningBytes;
inline constexpr std::size_t kDoseHistoryBytes = 4 + 4 * DoseHistory::kDoses;
inline constexpr std::size_t kMaterialEntryBytes = kMaterialEntryBytesV9 + kDoseHistoryBytes;
constexpr std::size_t material_table_bytes(std::size_t entry_bytes) {
  return 4 + entry_bytes * MaterialTable::kMaterials;
}
inline constexpr std::size_t kMaterialTableBytes = material_table_bytes(kMaterialEntryBytes);
// What a record holds after the baselines: nothing (version 5 and older), the material table
// (version 6), the table with what each material's fills learned (version 7), what its top-up
// pulses learned (version 8), the valve's timing its doses measured (version 9), and its last doses
// (version 10). In that order: each keeps what the one before it kept.
enum class MaterialsInRecord : std::uint8_t { none, table, learned, pulses, valve, doses };
constexpr std::size_t material_entry_bytes(MaterialsInRecord materials) {
  return materials == MaterialsInRecord::doses     ? kMaterialEntryBytes
         : materials == MaterialsInRecord::valve   ? kMaterialEntryBytesV9
         : materials == MaterialsInRecord::pulses  ? kMaterialEntryBytesV8
         : materials == MaterialsInRecord::learned ? kMaterialEntryBytesV7
         : materials == MaterialsInRecord::table   ? kMaterialEntryBytesV6
                                                   : 0;
}
// A record's size with `parameter_count` parameters (an older firmware's record has fewer) and the
// material table as its version keeps it.
constexpr std::size_t settings_record_size(std::size_t parameter_count,
                                           MaterialsInRecord materials = MaterialsInRecord::doses) {
  return 16 + 12 + 4 * parameter_count + kLearningEntryBytes * LearningTable::kEntries + kBaselineLearningBytes +
         (materials == MaterialsInRecord::none ? 0 : material_table_bytes(material_entry_bytes(materials)));
}
// Version 5 (before the material table) and version 4 (before the tolerance parameters too).
inline constexpr std::size_t kParametersV5 = static_cast<std::size_t>(ParameterId::topup_ms) + 1;
inline constexpr std::size_t kParametersV4 = static_cast<std::size_t>(ParameterId::oiml_class);
inline constexpr std::size_t kSettingsRecordSizeV9 = settings_record_size(kParameterCount, MaterialsInRecord::valve);
inline constexpr std::size_t kSettingsRecordSizeV8 = settings_record_size(kParameterCount, MaterialsInRecord::pulses);
inline constexpr std::size_t kSettingsRecordSizeV7 = settings_record_size(kParameterCount, MaterialsInRecord::learned);
inline constexpr std::size_t kSettingsRecordSizeV6 = settings_record_size(kParameterCount, MaterialsInRecord::table);
inline constexpr std::size_t kSettingsRecordSizeV5 = settings_record_size(kParametersV5, MaterialsInRecord::none);
inline constexpr std::size_t kSettingsRecordSizeV4 = settings_record_size(kParametersV4, MaterialsInRecord::none);
inline constexpr std::size_t kSettingsRecordSize = settings_record_size(kParameterCount);

std::uint32_t crc32(const std::uint8_t* data, std::size_t length);

// Writes the record; returns its size (kSettingsRecordSize) or 0 if `capacity` is too small.
std::size_t encode_settings(const PersistentSettings& settings, std::uint8_t* out, std::size_t capacity);
// False (and `settings` untouched) unless the record is complete and intact, and this firmware's or
// an older one (version 9, before the materials' last doses: none is kept; version 8, before the
// valve's timing per material: none is kept; version 7, before
// the top-up pulses' lessons: none is kept; version 6, before the
// materials' learned fields: nothing is learned; version 5, without the material table: material 0 is made from its density and
// class; version 4, without the tolerance parameters too: they take their defaults).
bool decode_settings(const std::uint8_t* data, std::size_t length, PersistentSettings& settings);

}  // namespace dynweigh::firmware
