#include "dynweigh/firmware/persistent_settings.hpp"

#include "dynweigh/firmware/little_endian.hpp"

#include <cmath>
#include <cstring>

namespace dynweigh::firmware {
namespace {

constexpr std::uint32_t kMagic = 0x48574E44;  // "DNWH"
// 2: the learning table; 3: the zero in whole counts; 4: what the pac and flowpreact baselines learned;
// 5: the tolerance parameters; 6: the discharge parameters and the material table; 7: what the model
// strategy's fills of each material measured; 8: what each material's top-up pulses taught; 9: the
// valve's timing each material's doses measured; 10: each material's last doses that ran full open
constexpr std::uint16_t kVersion = 10;
constexpr std::uint16_t kVersionBeforeDoseHistory = 9;
constexpr std::uint16_t kVersionBeforeValveTiming = 8;
constexpr std::uint16_t kVersionBeforePulses = 7;
constexpr std::uint16_t kVersionBeforeMaterialLearning = 6;
constexpr std::uint16_t kVersionBeforeMaterials = 5;
constexpr std::uint16_t kVersionBeforeTolerance = 4;

void put_f32(std::uint8_t* p, float f) {
  std::uint32_t v;
  std::memcpy(&v, &f, 4);
  put_u32(p, v);
}
float get_f32(const std::uint8_t* p) {
  const std::uint32_t v = get_u32(p);
  float f;
  std::memcpy(&f, &v, 4);
  return f;
}

void put_rls(std::uint8_t* p, const TwoParameterRls::State& s) {
  put_f32(p, s.theta1);
  put_f32(p + 4, s.theta2);
  put_f32(p + 8, s.p11);
  put_f32(p + 12, s.p12);
  put_f32(p + 16, s.p22);
  p[20] = std::uint8_t(s.fills);
  p[21] = std::uint8_t(s.fills >> 8);
}

// A law no learning can produce (not finite, its covariance not positive definite) is dropped: the
// strategy starts from its prior.
TwoParameterRls::State get_rls(const std::uint8_t* p) {
  TwoParameterRls::State s;
  s.theta1 = get_f32(p);
  s.theta2 = get_f32(p + 4);
  s.p11 = get_f32(p + 8);
  s.p12 = get_f32(p + 12);
  s.p22 = get_f32(p + 16);
  s.fills = std::uint16_t(p[20] | (p[21] << 8));
  return s.fills > 0 && TwoParameterRls::sane(s) ? s : TwoParameterRls::State{};
}

void put_baselines(std::uint8_t* p, const BaselineLearning& b) {
  put_rls(p, b.pac.spill);
  put_rls(p + kRlsStateBytes, b.pac.blind);
  std::uint8_t* f = p + 2 * kRlsStateBytes;
  put_f32(f, b.flowpreact.lag_s);
  f[4] = std::uint8_t(b.flowpreact.fills);
  f[5] = std::uint8_t(b.flowpreact.fills >> 8);
  put_rls(f + 8, b.flowpreact.blind);
}

// A lag beyond 10 s is no flowpreact lag.
constexpr float kLagLimitS = 10.0f;

BaselineLearning get_baselines(const std::uint8_t* p) {
  BaselineLearning b;
  b.pac.spill = get_rls(p);
  b.pac.blind = get_rls(p + kRlsStateBytes);
  const std::uint8_t* f = p + 2 * kRlsStateBytes;
  b.flowpreact.lag_s = get_f32(f);
  b.flowpreact.fills = std::uint16_t(f[4] | (f[5] << 8));
  if (b.flowpreact.fills == 0 || !(std::fabs(b.flowpreact.lag_s) <= kLagLimitS)) {
    b.flowpreact.lag_s = 0.0f;
    b.flowpreact.fills = 0;
  }
  b.flowpreact.blind = get_rls(f + 8);
  return b;
}

// The measured closes' spread in the bytes after the let-through's fills (zero in a record written
// before it was kept: nothing learned): the root of the mean square in 1/64 sigma, and the closes.
constexpr float kSpreadUnits = 64.0f;

void put_measured_close_spread(std::uint8_t* p, const MeasuredCloseSpread& spread) {
  const long root = std::lround(std::sqrt(spread.mean_square()) * kSpreadUnits);
  p[0] = std::uint8_t(root > 0xFF ? 0xFF : root);
  p[1] = spread.closes();
}

MeasuredCloseSpread get_measured_close_spread(const std::uint8_t* p) {
  const float root = float(p[0]) / kSpreadUnits;
  MeasuredCloseSpread spread;
  spread.restore(root * root, p[1]);
  return spread;
}

void put_material_learning(std::uint8_t* p, const MaterialLearning& learned) {
  put_rls(p, learned.open_time_law);
  put_f32(p + kRlsStateBytes, learned.close_let_through_s);
  p[kRlsStateBytes + 4] = std::uint8_t(learned.residual_fills);
  p[kRlsStateBytes + 5] = std::uint8_t(learned.residual_fills >> 8);
  put_measured_close_spread(p + kRlsStateBytes + 6, learned.measured_closes);
}

// A let-through no learning can produce (not finite, a second or more) is dropped, as a law that is not sane.
constexpr float kLetThroughLimitS = 1.0f;

MaterialLearning get_material_learning(const std::uint8_t* p) {
  MaterialLearning learned;
  learned.open_time_law = get_rls(p);
  learned.close_let_through_s = get_f32(p + kRlsStateBytes);
  learned.residual_fills = std::uint16_t(p[kRlsStateBytes + 4] | (p[kRlsStateBytes + 5] << 8));
  learned.measured_closes = get_measured_close_spread(p + kRlsStateBytes + 6);
  if (learned.residual_fills == 0 || !(std::fabs(learned.close_let_through_s) <= kLetThroughLimitS)) {
    learned.close_let_through_s = 0.0f;
    learned.residual_fills = 0;
  }
  return learned;
}

void put_pulse_law(std::uint8_t* p, const PulseLawLearning& law) {
  put_rls(p, law.law);
  put_f32(p + kRlsStateBytes, law.prior_flow_g_s);
  put_f32(p + kRlsStateBytes + 4, law.travel_s);
  p[kRlsStateBytes + 8] = law.pulses;
}

// Checked where it is used (TopUpPulseLaw::restore): a law that is not sane is not taken.
PulseLawLearning get_pulse_law(const std::uint8_t* p) {
  PulseLawLearning law;
  law.law = get_rls(p);
  law.prior_flow_g_s = get_f32(p + kRlsStateBytes);
  law.travel_s = get_f32(p + kRlsStateBytes + 4);
  law.pulses = p[kRlsStateBytes + 8];
  return law;
}

void put_valve_timing(std::uint8_t* p, const ValveTimingLearning& v) {
  put_f32(p, v.dead_s);
  put_f32(p + 4, v.travel_s);
  p[8] = std::uint8_t(v.dead_doses);
  p[9] = std::uint8_t(v.dead_doses >> 8);
  p[10] = std::uint8_t(v.travel_strokes);
  p[11] = std::uint8_t(v.travel_strokes >> 8);
}

// A timing no valve shows is dropped: the datasheet's stands.
ValveTimingLearning get_valve_timing(const std::uint8_t* p) {
  ValveTimingLearning v;
  v.dead_s = get_f32(p);
  v.travel_s = get_f32(p + 4);
  v.dead_doses = std::uint16_t(p[8] | (p[9] << 8));
  v.travel_strokes = std::uint16_t(p[10] | (p[11] << 8));
  return sane(v) ? v : ValveTimingLearning{};
}

void put_dose_history(std::uint8_t* p, const DoseHistory& doses) {
  p[0] = std::uint8_t(doses.size());
  p[1] = doses.next();
  for (std::size_t i = 0; i < DoseHistory::kDoses; ++i) {
    const DoseHistory::Entry& e = doses.entry(i);
    std::uint8_t* d = p + 4 + 4 * i;
    d[0] = std::uint8_t(e.open_100us);
    d[1] = std::uint8_t(e.open_100us >> 8);
    d[2] = std::uint8_t(e.final_g);
    d[3] = std::uint8_t(e.final_g >> 8);
  }
}

// A history no dose can leave (a count or a slot out of range, an empty or too light dose) is dropped.
DoseHistory get_dose_history(const std::uint8_t* p) {
  DoseHistory::Entry entries[DoseHistory::kDoses];
  for (std::size_t i = 0; i < DoseHistory::kDoses; ++i) {
    const std::uint8_t* d = p + 4 + 4 * i;
    entries[i].open_100us = std::uint16_t(d[0] | (d[1] << 8));
    entries[i].final_g = std::uint16_t(d[2] | (d[3] << 8));
  }
  DoseHistory doses;
  if (!doses.restore(entries, p[0], p[1])) return DoseHistory{};
  return doses;
}

// The slowest dead time the valve's feedback showed, in 0.1 ms, where the dose history's count and
// slot leave two bytes that records before it left zero: none seen. One no valve shows (a second or
// more) is none.
constexpr float kDeadTimeUnitMs = 0.1f;
constexpr float kLongestDeadTimeMs = 1000.0f;

void put_slowest_dead_time(std::uint8_t* p, float dead_ms) {
  const bool known = dead_ms > 0.0f && dead_ms < kLongestDeadTimeMs;
  const auto units = std::uint16_t(known ? std::lround(dead_ms / kDeadTimeUnitMs) : 0);
  p[0] = std::uint8_t(units);
  p[1] = std::uint8_t(units >> 8);
}

float get_slowest_dead_time(const std::uint8_t* p) {
  const float dead_ms = float(std::uint16_t(p[0] | (p[1] << 8))) * kDeadTimeUnitMs;
  return dead_ms < kLongestDeadTimeMs ? dead_ms : 0.0f;
}

void put_materials(std::uint8_t* p, const MaterialTable& table) {
  p[0] = std::uint8_t(table.selected());
  for (std::size_t n = 0; n < MaterialTable::kMaterials; ++n) {
    const Material& m = table.at(n);
    std::uint8_t* e = p + 4 + kMaterialEntryBytes * n;
    e[0] = m.defined ? 1 : 0;
    std::memcpy(e + 4, m.name, Material::kNameBytes);
    put_f32(e + 4 + Material::kNameBytes, m.density);
    put_f32(e + 8 + Material::kNameBytes, m.class_x);
    put_material_learning(e + kMaterialEntryBytesV6, m.learned);
    put_pulse_law(e + kMaterialEntryBytesV7, m.pulses.full);
    put_pulse_law(e + kMaterialEntryBytesV7 + kPulseLawLearningBytes, m.pulses.half);
    put_f32(e + kMaterialEntryBytesV8, m.learned.law_longest_open_s);
    put_valve_timing(e + kMaterialEntryBytesV8 + 4, m.learned.valve);
    put_dose_history(e + kMaterialEntryBytesV9, m.learned.doses);
    put_slowest_dead_time(e + kMaterialEntryBytesV9 + 2, m.valve_slowest_dead_ms);
  }
}

// An entry no console command can produce (a name not NUL-ended or not a name, a density or class
// out of range) is dropped: the material is undefined, and a selection of it falls back to 0.
// A version-6 table has no learned fields: every material starts with nothing learned; a version-7
// one no top-up pulses' lessons; a version-8 one no valve timing; a version-9 one no last doses.
MaterialTable get_materials(const std::uint8_t* p, const Parameters& parameters, MaterialsInRecord materials) {
  MaterialTable table(parameters);
  const std::size_t entry_bytes = material_entry_bytes(materials);
  // Each version keeps what the one before it kept, and more (MaterialsInRecord is in that order).
  const bool with_learning = materials >= MaterialsInRecord::learned;
  const bool with_pulses = materials >= MaterialsInRecord::pulses;
  const bool with_valve = materials >= MaterialsInRecord::valve;
  for (std::size_t n = 0; n < MaterialTable::kMaterials; ++n) {
    const std::uint8_t* e = p + 4 + entry_bytes * n;
    if (e[0] != 1) continue;
    Material m;
    std::memcpy(m.name, e + 4, Material::kNameBytes);
    m.defined = true;
    m.density = get_f32(e + 4 + Material::kNameBytes);
    m.class_x = get_f32(e + 8 + Material::kNameBytes);
    if (with_learning) m.learned = get_material_learning(e + kMaterialEntryBytesV6);
    if (with_pulses) {
      m.pulses.full = get_pulse_law(e + kMaterialEntryBytesV7);
      m.pulses.half = get_pulse_law(e + kMaterialEntryBytesV7 + kPulseLawLearningBytes);
    }
    if (with_valve) {
      m.learned.law_longest_open_s = get_f32(e + kMaterialEntryBytesV8);
      m.learned.valve = get_valve_timing(e + kMaterialEntryBytesV8 + 4);
    }
    if (materials >= MaterialsInRecord::doses) {
      m.learned.doses = get_dose_history(e + kMaterialEntryBytesV9);
      m.valve_slowest_dead_ms = get_slowest_dead_time(e + kMaterialEntryBytesV9 + 2);
    }
    if (MaterialTable::valid(m)) table.restore(n, m);
  }
  const std::size_t selected = p[0] < MaterialTable::kMaterials && table.at(p[0]).defined ? p[0] : 0;
  table.restore_selection(selected);
  // The parameters in force are the selected material's.
  table.follow_parameter(ParameterId::density, parameters);
  table.follow_parameter(ParameterId::oiml_class, parameters);
  return table;
}

}  // namespace

std::uint32_t crc32(const std::uint8_t* data, std::size_t length) {
  std::uint32_t crc = 0xFFFFFFFFu;
  for (std::size_t i = 0; i < length; ++i) {
    crc ^= data[i];
    for (int bit = 0; bit < 8; ++bit) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

// Layout, little-endian: magic u32, version u16, parameter count u16, length u32, crc u32 (over
// everything after it), zero i32, zero fraction f32, span f32, parameters f32 each, learning table,
// the baselines' learned laws, the material table.
std::size_t encode_settings(const PersistentSettings& settings, std::uint8_t* out, std::size_t capacity) {
  if (capacity < kSettingsRecordSize) return 0;
  std::memset(out, 0, kSettingsRecordSize);
  put_u32(out, kMagic);
  out[4] = std::uint8_t(kVersion);
  out[5] = std::uint8_t(kVersion >> 8);
  out[6] = std::uint8_t(kParameterCount);
  out[7] = 0;
  put_u32(out + 8, std::uint32_t(kSettingsRecordSize));
  std::uint8_t* body = out + 16;
  put_u32(body, std::uint32_t(settings.calibration.zero_counts));
  put_f32(body + 4, settings.calibration.zero_fraction);
  put_f32(body + 8, settings.calibration.counts_per_gram);
  // Flags live in the top bits of the parameter count's pad byte to keep the body float-aligned.
  out[7] = std::uint8_t((settings.calibration.zero_set ? 1 : 0) | (settings.calibration.span_set ? 2 : 0));
  for (std::size_t i = 0; i < kParameterCount; ++i) put_f32(body + 12 + 4 * i, settings.parameters.raw()[i]);
  std::uint8_t* table = body + 12 + 4 * kParameterCount;
  for (std::size_t i = 0; i < LearningTable::kEntries; ++i) {
    const LearningTable::Entry& e = settings.learning.entry(i);
    std::uint8_t* p = table + kLearningEntryBytes * i;
    p[0] = e.used ? 1 : 0;
    p[1] = e.key.target_bucket;
    p[2] = e.key.fall_bucket;
    p[3] = e.key.flow_bucket;
    put_f32(p + 4, e.correction_g);
    p[8] = std::uint8_t(e.fills);
    p[9] = std::uint8_t(e.fills >> 8);
  }
  std::uint8_t* baselines = table + kLearningEntryBytes * LearningTable::kEntries;
  put_baselines(baselines, settings.baselines);
  put_materials(baselines + kBaselineLearningBytes, settings.materials);
  put_u32(out + 12, crc32(out + 16, kSettingsRecordSize - 16) ^ crc32(out, 12));
  return kSettingsRecordSize;
}

bool decode_settings(const std::uint8_t* data, std::size_t length, PersistentSettings& settings) {
  if (length < 16 || get_u32(data) != kMagic) return false;
  const int version = data[4] | (data[5] << 8);
  const std::size_t parameter_count = version == kVersion || version == kVersionBeforeDoseHistory ||
                                              version == kVersionBeforeValveTiming ||
                                              version == kVersionBeforePulses ||
                                              version == kVersionBeforeMaterialLearning
                                          ? kParameterCount
                                      : version == kVersionBeforeMaterials ? kParametersV5
                                      : version == kVersionBeforeTolerance ? kParametersV4
                                                                           : 0;
  const MaterialsInRecord materials = version == kVersion                         ? MaterialsInRecord::doses
                                      : version == kVersionBeforeDoseHistory      ? MaterialsInRecord::valve
                                      : version == kVersionBeforeValveTiming      ? MaterialsInRecord::pulses
                                      : version == kVersionBeforePulses           ? MaterialsInRecord::learned
                                      : version == kVersionBeforeMaterialLearning ? MaterialsInRecord::table
                                                                                  : MaterialsInRecord::none;
  const std::size_t record_size = settings_record_size(parameter_count, materials);
  if (parameter_count == 0 || data[6] != parameter_count || length < record_size) return false;
  if (get_u32(data + 8) != record_size) return false;
  if (get_u32(data + 12) != (crc32(data + 16, record_size - 16) ^ crc32(data, 12))) return false;
  PersistentSettings decoded;
  const std::uint8_t* body = data + 16;
  decoded.calibration.zero_counts = std::int32_t(get_u32(body));
  decoded.calibration.zero_fraction = get_f32(body + 4);
  decoded.calibration.counts_per_gram = get_f32(body + 8);
  decoded.calibration.zero_set = (data[7] & 1) != 0;
  decoded.calibration.span_set = (data[7] & 2) != 0;
  // A calibration no `zero` or `cal` can produce (a fraction of a count outside [0, 1), a span not
  // finite or not positive) is dropped: the indicator then asks for calibration instead of weighing
  // with it (found by fuzz/settings_fuzzer).
  Calibration& cal = decoded.calibration;
  if (!(cal.zero_fraction >= 0.0f && cal.zero_fraction < 1.0f) || !std::isfinite(cal.counts_per_gram) ||
      (cal.span_set && !(cal.counts_per_gram > 0.0f))) {
    cal = Calibration{};
  }
  for (std::size_t i = 0; i < parameter_count; ++i) {
    // A value outside today's range (an older firmware's table) falls back to the default, and so
    // does a read-only one (jiffy_ms: the board's, whatever an older firmware stored).
    decoded.parameters.set(static_cast<ParameterId>(i), get_f32(body + 12 + 4 * i));
  }
  const std::uint8_t* table = body + 12 + 4 * parameter_count;
  for (std::size_t i = 0; i < LearningTable::kEntries; ++i) {
    const std::uint8_t* p = table + kLearningEntryBytes * i;
    LearningTable::Entry& e = decoded.learning.entry(i);
    e.used = p[0] == 1;
    e.key = {p[1], p[2], p[3]};
    e.correction_g = get_f32(p + 4);
    e.fills = std::uint16_t(p[8] | (p[9] << 8));
    // Learning moves a correction by at most kMaximumStepG a fill: more is not a learned value.
    const bool reachable = std::fabs(e.correction_g) <= LearningTable::kMaximumStepG * float(e.fills);
    if (!e.used || !std::isfinite(e.correction_g) || !reachable) e = LearningTable::Entry{};
  }
  const std::uint8_t* baselines = table + kLearningEntryBytes * LearningTable::kEntries;
  decoded.baselines = get_baselines(baselines);
  // Before the table: material 0, selected, is the one the parameters describe.
  decoded.materials = materials != MaterialsInRecord::none
                          ? get_materials(baselines + kBaselineLearningBytes, decoded.parameters, materials)
                          : MaterialTable(decoded.parameters);
  settings = decoded;
  return true;
}

}  // namespace dynweigh::firmware
