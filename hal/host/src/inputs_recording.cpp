#include "dynweigh/hal/host/inputs_recording.hpp"

#include <cerrno>
#include <cstring>
#include <stdexcept>


namespace dynweigh::hal::host {
namespace {

constexpr std::uint8_t kJiffyTag = 'J';
constexpr std::uint8_t kFlagFresh = 0x01;
constexpr std::uint8_t kFlagOutputs = 0x02;
// bits 2-3: the board's word on the last save (firmware::SettingsSave: 0 none, 1 saved, 2 failed)
constexpr unsigned kSaveShift = 2;
constexpr std::uint8_t kFlagSaveMask = 0x3u << kSaveShift;
// bits 4-5 (version 2 on): the link's status (firmware::LinkStatus: 0 ok, 1 silent, 2 bus off)
constexpr unsigned kLinkShift = 4;
constexpr std::uint8_t kFlagLinkMask = 0x3u << kLinkShift;
// bits 6-7 (version 3 on): the discharge gate's position (firmware::GatePosition: 0 closed, 1 moving, 3 open)
constexpr unsigned kGateShift = 6;
constexpr std::uint8_t kFlagGateMask = 0x3u << kGateShift;
constexpr std::uint8_t kBitBusy = 0x01;
constexpr std::uint8_t kBitSettingsChanged = 0x02;
constexpr std::uint8_t kBitGateOpen = 0x04;  // version 3 on
constexpr std::size_t kMaxSourceLength = 1024;

// Little-endian encoding, whatever the host's byte order.
void put_u8(std::string& out, std::uint8_t v) { out.push_back(char(v)); }
void put_u16(std::string& out, std::uint16_t v) {
  for (int i = 0; i < 2; ++i) out.push_back(char((v >> (8 * i)) & 0xffu));
}
void put_u32(std::string& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(char((v >> (8 * i)) & 0xffu));
}

std::uint32_t bits_of(float value) {
  std::uint32_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  return bits;
}

float float_of(std::uint32_t bits) {
  float value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

std::uint32_t crc_of(const std::string& bytes) {
  return firmware::crc32(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
}

// Reads exactly what the format says comes next, keeping the bytes for the record's CRC.
class FieldReader {
 public:
  FieldReader(std::FILE* file, const std::string& path, std::string& consumed)
      : file_(file), path_(path), consumed_(consumed) {}

  // False only if the file ends before the first byte (a clean end between records).
  bool try_u8(std::uint8_t& v) {
    const int c = std::fgetc(file_);
    if (c == EOF) return false;
    v = std::uint8_t(c);
    consumed_.push_back(char(v));
    return true;
  }
  std::string bytes(std::size_t n, const char* what) {
    std::string out(n, '\0');
    if (n > 0 && std::fread(out.data(), 1, n, file_) != n) truncated(what);
    consumed_ += out;
    return out;
  }
  std::uint8_t u8(const char* what) { return std::uint8_t(bytes(1, what)[0]); }
  std::uint16_t u16(const char* what) {
    const std::string b = bytes(2, what);
    return std::uint16_t(std::uint8_t(b[0]) | std::uint16_t(std::uint8_t(b[1]) << 8));
  }
  std::uint32_t u32(const char* what) {
    const std::string b = bytes(4, what);
    std::uint32_t v = 0;
    for (int i = 3; i >= 0; --i) v = (v << 8) | std::uint8_t(b[std::size_t(i)]);
    return v;
  }
  // The CRC is read outside the consumed bytes it checks.
  std::uint32_t crc(const char* what) {
    const std::size_t before = consumed_.size();
    const std::uint32_t v = u32(what);
    consumed_.resize(before);
    return v;
  }
  [[noreturn]] void truncated(const char* what) const {
    throw std::runtime_error(path_ + ": truncated recording (ends inside " + what + ")");
  }

 private:
  std::FILE* file_;
  const std::string& path_;
  std::string& consumed_;
};

}  // namespace

firmware::Inputs RecordedJiffy::inputs() const {
  firmware::Inputs in;
  in.jiffy = jiffy;
  in.load_cell = load_cell;
  in.valve_position = valve_position;
  in.gate_position = gate_position;
  // Not recorded: every ingredient valve is taken to be there. A recorded batch replays (the valve
  // feedback recorded is the commanded ingredient's); one the board refused for a missing valve does not.
  in.ingredient_valves = 0xFF;
  in.console_rx = console_rx.empty() ? nullptr : console_rx.data();
  in.console_rx_length = console_rx.size();
  in.settings_save = settings_save;
  return in;
}

bool same_outputs(const firmware::Outputs& a, const firmware::Outputs& b, bool telemetry) {
  const bool acted_on = a.valve == b.valve && a.gate == b.gate && a.valve_delay_100us == b.valve_delay_100us &&
                        a.answered_counter == b.answered_counter && a.state == b.state &&
                        a.weight_100mg == b.weight_100mg && a.settings_changed == b.settings_changed &&
                        a.busy == b.busy;
  return acted_on && (!telemetry || (bits_of(a.filtered_g) == bits_of(b.filtered_g) &&
                                     bits_of(a.net_g) == bits_of(b.net_g) &&
                                     bits_of(a.predicted_g) == bits_of(b.predicted_g) && a.fault == b.fault));
}

// ---------------------------------------------------------------------------------------------
InputsRecordingWriter::InputsRecordingWriter(const std::string& path, const firmware::PersistentSettings& settings,
                                             const std::string& source, std::uint32_t last_sequence)
    : file_(std::fopen(path.c_str(), "wb")), path_(path) {
  if (!file_) throw std::runtime_error("cannot write " + path + ": " + std::strerror(errno));
  std::uint8_t record[firmware::kSettingsRecordSize];
  const std::size_t size = firmware::encode_settings(settings, record, sizeof record);
  std::string header(kInputsRecordingMagic, kInputsRecordingMagicLength);
  put_u32(header, kInputsRecordingVersion);
  put_u32(header, std::uint32_t(size));
  header.append(reinterpret_cast<const char*>(record), size);
  const std::string note = source.substr(0, kMaxSourceLength);
  put_u16(header, std::uint16_t(note.size()));
  header += note;
  put_u32(header, last_sequence);
  put_u32(header, crc_of(header));
  if (std::fwrite(header.data(), 1, header.size(), file_) != header.size() || std::fflush(file_) != 0) {
    throw std::runtime_error("cannot write " + path);
  }
}

InputsRecordingWriter::~InputsRecordingWriter() {
  if (file_) std::fclose(file_);
}

void InputsRecordingWriter::write(const RecordedJiffy& j) {
  if (j.console_rx.size() > kMaxRecordedRxBytes || j.console_tx.size() > kMaxRecordedTxBytes) {
    throw std::runtime_error(path_ + ": jiffy " + std::to_string(j.jiffy) + " has more console bytes than a recording holds");
  }
  std::string r;
  put_u8(r, kJiffyTag);
  put_u32(r, j.jiffy);
  put_u32(r, std::uint32_t(j.load_cell.raw_counts));
  put_u16(r, j.load_cell.counter);
  put_u8(r, j.load_cell.status);
  put_u8(r, std::uint8_t((j.load_cell.fresh ? kFlagFresh : 0) | (j.has_outputs ? kFlagOutputs : 0) |
                         (static_cast<unsigned>(j.settings_save) << kSaveShift) |
                         (static_cast<unsigned>(j.load_cell.link) << kLinkShift) |
                         (static_cast<unsigned>(j.gate_position) << kGateShift)));
  put_u8(r, static_cast<std::uint8_t>(j.valve_position));
  put_u16(r, std::uint16_t(j.console_rx.size()));
  r += j.console_rx;
  if (j.has_outputs) {
    const firmware::Outputs& o = j.outputs;
    put_u8(r, static_cast<std::uint8_t>(o.valve));
    put_u8(r, o.valve_delay_100us);
    put_u16(r, o.answered_counter);
    put_u8(r, static_cast<std::uint8_t>(o.state));
    put_u32(r, std::uint32_t(o.weight_100mg));
    put_u8(r, std::uint8_t((o.busy ? kBitBusy : 0) | (o.settings_changed ? kBitSettingsChanged : 0) |
                           (o.gate == firmware::GateCommand::open ? kBitGateOpen : 0)));
    put_u32(r, bits_of(o.filtered_g));
    put_u32(r, bits_of(o.net_g));
    put_u32(r, bits_of(o.predicted_g));
    put_u8(r, static_cast<std::uint8_t>(o.fault));
    put_u32(r, std::uint32_t(j.console_tx.size()));
    r += j.console_tx;
  }
  put_u32(r, crc_of(r));
  if (std::fwrite(r.data(), 1, r.size(), file_) != r.size() || std::fflush(file_) != 0) {
    throw std::runtime_error("cannot write " + path_ + ": " + std::strerror(errno));
  }
  ++jiffies_;
}

void InputsRecordingWriter::record(const JiffyRecord& jiffy) {
  RecordedJiffy j;
  j.jiffy = jiffy.jiffy;
  j.load_cell = jiffy.load_cell;
  j.valve_position = jiffy.valve_position;
  j.gate_position = jiffy.gate_position;
  j.console_rx.assign(jiffy.console_rx, jiffy.console_rx_length);
  j.settings_save = jiffy.settings_save;
  j.has_outputs = true;
  j.has_telemetry = true;
  j.outputs = jiffy.outputs;
  j.console_tx.swap(pending_tx_);
  pending_tx_.clear();
  write(j);
}

// ---------------------------------------------------------------------------------------------
bool InputsRecordingReader::is_recording(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return false;
  char magic[kInputsRecordingMagicLength];
  const bool yes = std::fread(magic, 1, sizeof magic, f) == sizeof magic &&
                   std::memcmp(magic, kInputsRecordingMagic, sizeof magic) == 0;
  std::fclose(f);
  return yes;
}

InputsRecordingReader::InputsRecordingReader(const std::string& path)
    : file_(std::fopen(path.c_str(), "rb")), path_(path) {
  if (!file_) throw std::runtime_error("cannot read " + path + ": " + std::strerror(errno));
  std::string header;
  FieldReader in(file_, path_, header);
  if (in.bytes(kInputsRecordingMagicLength, "the header") != std::string(kInputsRecordingMagic, kInputsRecordingMagicLength)) {
    throw std::runtime_error(path + ": not an inputs recording (no dynweigh-inputs header)");
  }
  version_ = in.u32("the header");
  if (version_ < kOldestInputsRecordingVersion || version_ > kInputsRecordingVersion) {
    throw std::runtime_error(path + ": inputs recording version " + std::to_string(version_) + ", this build reads " +
                             std::to_string(kOldestInputsRecordingVersion) + " to " +
                             std::to_string(kInputsRecordingVersion));
  }
  const std::uint32_t settings_size = in.u32("the header");
  // An earlier firmware's record is smaller; decode_settings below knows which versions it reads.
  if (settings_size > firmware::kSettingsRecordSize) {
    throw std::runtime_error(path + ": settings record of " + std::to_string(settings_size) +
                             " bytes, more than this build's " + std::to_string(firmware::kSettingsRecordSize) +
                             " (a newer firmware's recording)");
  }
  const std::string settings = in.bytes(settings_size, "the settings");
  const std::uint16_t source_length = in.u16("the header");
  if (source_length > kMaxSourceLength) throw std::runtime_error(path + ": damaged header (source note too long)");
  source_ = in.bytes(source_length, "the header");
  if (version_ >= 2) last_sequence_ = in.u32("the header");
  const std::uint32_t expected = in.crc("the header");
  if (crc_of(header) != expected) throw std::runtime_error(path + ": damaged header (CRC mismatch)");
  if (!firmware::decode_settings(reinterpret_cast<const std::uint8_t*>(settings.data()), settings.size(), settings_)) {
    throw std::runtime_error(path + ": the recorded settings are damaged or of another firmware version");
  }
}

InputsRecordingReader::~InputsRecordingReader() {
  if (file_) std::fclose(file_);
}

bool InputsRecordingReader::next(RecordedJiffy& j) {
  std::string record;
  FieldReader in(file_, path_, record);
  std::uint8_t tag = 0;
  if (!in.try_u8(tag)) return false;
  const std::string where = path_ + ": record " + std::to_string(records_ + 1);
  if (tag != kJiffyTag) throw std::runtime_error(where + " is damaged (bad tag)");
  j = RecordedJiffy{};
  j.jiffy = in.u32("a record");
  j.load_cell.raw_counts = std::int32_t(in.u32("a record"));
  j.load_cell.counter = in.u16("a record");
  j.load_cell.status = in.u8("a record");
  const std::uint8_t flags = in.u8("a record");
  const std::uint8_t position = in.u8("a record");
  const unsigned save = (flags & kFlagSaveMask) >> kSaveShift;
  const unsigned link = (flags & kFlagLinkMask) >> kLinkShift;
  const unsigned gate = (flags & kFlagGateMask) >> kGateShift;
  const std::uint8_t known_flags = version_ >= 3   ? kFlagFresh | kFlagOutputs | kFlagSaveMask | kFlagLinkMask | kFlagGateMask
                                   : version_ >= 2 ? kFlagFresh | kFlagOutputs | kFlagSaveMask | kFlagLinkMask
                                                   : kFlagFresh | kFlagOutputs | kFlagSaveMask;
  if ((flags & ~known_flags) != 0 || position > 3 || save > static_cast<unsigned>(firmware::SettingsSave::failed) ||
      link > static_cast<unsigned>(firmware::LinkStatus::bus_off) || gate == 2) {
    throw std::runtime_error(where + " is damaged (bad flags)");
  }
  j.settings_save = static_cast<firmware::SettingsSave>(save);
  j.load_cell.link = static_cast<firmware::LinkStatus>(link);
  j.load_cell.fresh = (flags & kFlagFresh) != 0;
  j.valve_position = static_cast<firmware::ValvePosition>(position);
  j.gate_position = static_cast<firmware::GatePosition>(gate);
  const std::uint16_t rx_length = in.u16("a record");
  if (rx_length > kMaxRecordedRxBytes) throw std::runtime_error(where + " is damaged (console input too long)");
  j.console_rx = in.bytes(rx_length, "a record");
  j.has_outputs = (flags & kFlagOutputs) != 0;
  if (j.has_outputs) {
    firmware::Outputs& o = j.outputs;
    const std::uint8_t valve = in.u8("a record");
    o.valve_delay_100us = in.u8("a record");
    o.answered_counter = in.u16("a record");
    const std::uint8_t state = in.u8("a record");
    o.weight_100mg = std::int32_t(in.u32("a record"));
    const std::uint8_t bits = in.u8("a record");
    const std::uint8_t known_bits = version_ >= 3 ? kBitBusy | kBitSettingsChanged | kBitGateOpen : kBitBusy | kBitSettingsChanged;
    if (valve > 2 || state > 3 || (bits & ~known_bits) != 0) {
      throw std::runtime_error(where + " is damaged (bad outputs)");
    }
    o.valve = static_cast<firmware::ValveCommand>(valve);
    o.state = static_cast<firmware::IndicatorState>(state);
    o.busy = (bits & kBitBusy) != 0;
    o.settings_changed = (bits & kBitSettingsChanged) != 0;
    o.gate = (bits & kBitGateOpen) != 0 ? firmware::GateCommand::open : firmware::GateCommand::closed;
    if (version_ >= 2) {
      o.filtered_g = float_of(in.u32("a record"));
      o.net_g = float_of(in.u32("a record"));
      o.predicted_g = float_of(in.u32("a record"));
      o.fault = static_cast<firmware::Fault>(in.u8("a record"));  // a damaged byte fails the CRC below
      j.has_telemetry = true;
    }
    const std::uint32_t tx_length = in.u32("a record");
    if (tx_length > kMaxRecordedTxBytes) throw std::runtime_error(where + " is damaged (console output too long)");
    j.console_tx = in.bytes(tx_length, "a record");
  }
  const std::uint32_t expected = in.crc("a record");
  if (crc_of(record) != expected) throw std::runtime_error(where + " is damaged (CRC mismatch)");
  ++records_;
  return true;
}

}  // namespace dynweigh::hal::host
