#pragma once
// A recording of everything the indicator saw, jiffy by jiffy (every firmware::Inputs, console
// bytes included), with the settings it started from: `dynweigh-fw --record FILE` writes it,
// `dynweigh replay FILE` feeds it through the same Indicator::step and gets the same decisions,
// bit for bit. Like ArduPilot's AP_DAL log, it holds the inputs, not the plant, so it replays on
// any build without the simulator, whatever plant the live run had (in-process or on CAN).
//
// The writer is a hal::JiffyRecorder: a board hands it each jiffy's record as run_one_jiffy takes
// it, so what is written is what the indicator saw, nothing rebuilt after the fact. Each jiffy also
// carries the Outputs and console bytes the live run produced, so a replay can prove it matched
// instead of asserting it.
//
// File format, little-endian throughout. Version 3 (written now):
//   header  "dynweigh-inputs\n" (16 bytes), u32 version, u32 settings size, the settings record
//           (firmware::encode_settings: magic, version, CRC), u16 source length, source text
//           (a free note: which program and plant made it), u32 the last result's sequence number
//           when the recording began, u32 CRC-32 of the header so far
//   jiffy   u8 'J', u32 jiffy, i32 raw counts, u16 sample counter, u8 status, u8 flags
//           (bit0 fresh sample, bit1 outputs follow, bits 2-3 the last save: 0 none, 1 saved,
//           2 failed, bits 4-5 the link: 0 ok, 1 silent, 2 bus off, bits 6-7 the discharge gate's
//           position: 0 closed, 1 moving, 3 open), u8 valve position,
//           u16 rx length, rx bytes,
//           [outputs: u8 valve, u8 delay_100us, u16 answered counter, u8 state, i32 weight_100mg,
//           u8 bits (bit0 busy, bit1 settings_changed, bit2 gate commanded open), f32 filtered_g, f32 net_g, f32 predicted_g,
//           u8 fault, u32 tx length, tx bytes],
//           u32 CRC-32 of the record from 'J' on
// Version 2 (still read): no gate bits (the gate closed, never commanded open).
// Version 1 (still read): no sequence number in the header, no link bits (always ok), and the
// outputs without the four telemetry fields.
// A file ends after its last complete record; a file that ends inside a record is truncated.
#include <cstdint>
#include <cstdio>
#include <string>

#include "dynweigh/firmware/indicator.hpp"
#include "dynweigh/hal/jiffy_record.hpp"

namespace dynweigh::hal::host {

inline constexpr char kInputsRecordingMagic[] = "dynweigh-inputs\n";
inline constexpr std::size_t kInputsRecordingMagicLength = 16;
inline constexpr std::uint32_t kInputsRecordingVersion = 3;
inline constexpr std::uint32_t kOldestInputsRecordingVersion = 1;
// Bounds a reader enforces so a damaged file is reported, never believed: a jiffy's console input
// cannot exceed what a board reads in one jiffy by much, nor its output the indicator's ring.
inline constexpr std::size_t kMaxRecordedRxBytes = 4096;
inline constexpr std::size_t kMaxRecordedTxBytes = 1u << 20;

struct RecordedJiffy {
  std::uint32_t jiffy = 0;
  firmware::LoadCellInput load_cell;
  firmware::ValvePosition valve_position = firmware::ValvePosition::closed;
  firmware::GatePosition gate_position = firmware::GatePosition::closed;
  std::string console_rx;
  firmware::SettingsSave settings_save = firmware::SettingsSave::none;
  bool has_outputs = false;    // what the live run decided, for checking a replay
  bool has_telemetry = false;  // and its telemetry (filtered, net, predicted grams, fault): version 2 on
  firmware::Outputs outputs;
  std::string console_tx;

  // The Inputs to step an indicator with; valid while this RecordedJiffy lives unchanged.
  firmware::Inputs inputs() const;
};

// True if every field a board acts on is the same, and with `telemetry` the tools' fields too
// (bit for bit: a replay runs the same float arithmetic).
bool same_outputs(const firmware::Outputs& a, const firmware::Outputs& b, bool telemetry = false);

class InputsRecordingWriter final : public JiffyRecorder {
 public:
  // Throws std::runtime_error (one line) if the file cannot be created. `last_sequence`: the
  // number of the board's newest result, so a replay numbers the next RESULT as the live run did.
  InputsRecordingWriter(const std::string& path, const firmware::PersistentSettings& settings,
                        const std::string& source, std::uint32_t last_sequence = 0);
  // The recording of `indicator` from its next jiffy on: its settings and result numbering now.
  InputsRecordingWriter(const std::string& path, const firmware::Indicator& indicator, const std::string& source)
      : InputsRecordingWriter(path, indicator.settings(), source, indicator.last_sequence()) {}
  ~InputsRecordingWriter() override;
  InputsRecordingWriter(const InputsRecordingWriter&) = delete;
  InputsRecordingWriter& operator=(const InputsRecordingWriter&) = delete;

  // Appends one jiffy and flushes it, so a program killed between jiffies (a pty console runs
  // until it is) leaves a complete file. Throws on a write error.
  void write(const RecordedJiffy& jiffy);
  std::uint64_t jiffies() const { return jiffies_; }

  // hal::JiffyRecorder: a board's jiffies as run_one_jiffy takes them.
  void console_sent(const char* data, std::size_t length) override { pending_tx_.append(data, length); }
  void record(const JiffyRecord& jiffy) override;

 private:
  std::FILE* file_ = nullptr;
  std::string path_;
  std::uint64_t jiffies_ = 0;
  std::string pending_tx_;  // this jiffy's console bytes, until its record comes
};

class InputsRecordingReader {
 public:
  // Reads and checks the header; throws std::runtime_error (one line) if the file is not a
  // recording, of another version, or damaged.
  explicit InputsRecordingReader(const std::string& path);
  ~InputsRecordingReader();
  InputsRecordingReader(const InputsRecordingReader&) = delete;
  InputsRecordingReader& operator=(const InputsRecordingReader&) = delete;

  // True if the file starts with the recording's magic (whatever its version).
  static bool is_recording(const std::string& path);

  const firmware::PersistentSettings& settings() const { return settings_; }
  const std::string& source() const { return source_; }
  std::uint32_t version() const { return version_; }
  // The board's newest result number when the recording began (0 in a version 1 recording).
  std::uint32_t last_sequence() const { return last_sequence_; }

  // The next jiffy; false at the end of the file. Throws on a truncated or damaged record.
  bool next(RecordedJiffy& jiffy);

 private:
  std::FILE* file_ = nullptr;
  std::string path_;
  firmware::PersistentSettings settings_;
  std::string source_;
  std::uint32_t version_ = 0;
  std::uint32_t last_sequence_ = 0;
  std::uint64_t records_ = 0;
};

}  // namespace dynweigh::hal::host
