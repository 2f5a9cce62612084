#pragma once
// A recording of everything the indicator saw, jiffy by jiffy (every firmware::Inputs, console
// bytes included), with the settings it started from: `dynweigh-fw --record FILE` writes it,
// `dynweigh replay FILE` feeds it through the same Indicator::step and gets the same decisions,
// bit for bit. Like ArduPilot's AP_DAL log, it holds the inputs, not the
// plant, so it replays on any build without the simulator.
//
// Each jiffy also carries the Outputs and console bytes the live run produced, so a replay can
// prove it matched instead of asserting it.
//
// File format, version 1, little-endian throughout:
//   header  "dynweigh-inputs\n" (16 bytes), u32 version, u32 settings size, the settings record
//           (firmware::encode_settings: magic, version, CRC), u16 source length, source text
//           (a free note: which program and plant made it), u32 CRC-32 of the header so far
//   jiffy   u8 'J', u32 jiffy, i32 raw counts, u16 sample counter, u8 status, u8 flags
//           (bit0 fresh sample, bit1 outputs follow, bits 2-3 the last save: 0 none, 1 saved,
//           2 failed), u8 valve position, u16 rx length, rx bytes,
//           [outputs: u8 valve, u8 delay_100us, u16 answered counter, u8 state, i32 weight_100mg,
//           u8 bits (bit0 busy, bit1 settings_changed), u32 tx length, tx bytes],
//           u32 CRC-32 of the record from 'J' on
// A file ends after its last complete record; a file that ends inside a record is truncated.
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <utility>

#include "dynweigh/firmware/indicator.hpp"
#include "dynweigh/hal/ports.hpp"

namespace dynweigh::hal::host {

class LockstepSession;

inline constexpr char kInputsRecordingMagic[] = "dynweigh-inputs\n";
inline constexpr std::size_t kInputsRecordingMagicLength = 16;
inline constexpr std::uint32_t kInputsRecordingVersion = 1;
// Bounds a reader enforces so a damaged file is reported, never believed: a jiffy's console input
// cannot exceed what a board reads in one jiffy by much, nor its output the indicator's ring.
inline constexpr std::size_t kMaxRecordedRxBytes = 4096;
inline constexpr std::size_t kMaxRecordedTxBytes = 1u << 20;

struct RecordedJiffy {
  std::uint32_t jiffy = 0;
  firmware::LoadCellInput load_cell;
  firmware::ValvePosition valve_position = firmware::ValvePosition::closed;
  std::string console_rx;
  firmware::SettingsSave settings_save = firmware::SettingsSave::none;
  bool has_outputs = false;  // what the live run decided, for checking a replay
  firmware::Outputs outputs;
  std::string console_tx;

  // The Inputs to step an indicator with; valid while this RecordedJiffy lives unchanged.
  firmware::Inputs inputs() const;
};

// True if every field a board acts on is the same.
bool same_outputs(const firmware::Outputs& a, const firmware::Outputs& b);

class InputsRecordingWriter {
 public:
  // Throws std::runtime_error (one line) if the file cannot be created.
  InputsRecordingWriter(const std::string& path, const firmware::PersistentSettings& settings,
                        const std::string& source);
  ~InputsRecordingWriter();
  InputsRecordingWriter(const InputsRecordingWriter&) = delete;
  InputsRecordingWriter& operator=(const InputsRecordingWriter&) = delete;

  // Appends one jiffy and flushes it, so a program killed between jiffies (a pty console runs
  // until it is) leaves a complete file. Throws on a write error.
  void write(const RecordedJiffy& jiffy);
  std::uint64_t jiffies() const { return jiffies_; }

 private:
  std::FILE* file_ = nullptr;
  std::string path_;
  std::uint64_t jiffies_ = 0;
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

  // The next jiffy; false at the end of the file. Throws on a truncated or damaged record.
  bool next(RecordedJiffy& jiffy);

 private:
  std::FILE* file_ = nullptr;
  std::string path_;
  firmware::PersistentSettings settings_;
  std::string source_;
  std::uint32_t version_ = 0;
  std::uint64_t records_ = 0;
};

// A console port that passes everything through and keeps this jiffy's bytes in both directions.
// It takes all the indicator has each jiffy (the default ConsolePort::writable), as a replay drains
// it, so the recorded jiffies replay exactly.
class ConsoleTap final : public ConsolePort {
 public:
  explicit ConsoleTap(ConsolePort& inner) : inner_(inner) {}
  std::size_t read(char* destination, std::size_t capacity) override;
  void write(const char* data, std::size_t length) override;
  std::string take_rx() { return std::exchange(rx_, {}); }
  std::string take_tx() { return std::exchange(tx_, {}); }

 private:
  ConsolePort& inner_;
  std::string rx_, tx_;
};

// Steps a LockstepSession and records each jiffy's Inputs and Outputs (`dynweigh-fw --record`).
// The session keeps its ports to itself, so the recorder rebuilds the Inputs from what it does
// show (the console bytes it passes, the valve feedback read just before the step, the raw
// sample, the answered counter) and proves the result as it goes: a shadow indicator built from
// the same settings steps on the rebuilt Inputs and must decide exactly what the live one did.
// The load cell's status bits are the one thing not shown; the shadow finds the bits that
// reproduce the live indicator's fault. A jiffy it cannot reproduce throws, so a recording that
// exists replays bit for bit.
class LockstepRecorder {
 public:
  LockstepRecorder(const std::string& path, LockstepSession& session, const std::string& source);
  ~LockstepRecorder();
  firmware::Outputs step(ConsolePort& console);
  std::uint64_t jiffies() const { return writer_.jiffies(); }

 private:
  LockstepSession& session_;
  InputsRecordingWriter writer_;
  std::unique_ptr<firmware::Indicator> shadow_;
};

}  // namespace dynweigh::hal::host
