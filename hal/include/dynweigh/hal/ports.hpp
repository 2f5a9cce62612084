#pragma once
// The hardware the indicator needs, as small ports. A target implements each; the control
// loop (control_loop.hpp) is the same on all of them. Thin virtual interfaces at the edge: one
// indirect call per port per jiffy, and no RTTI needed.
#include <cstddef>
#include <cstdint>

#include "dynweigh/firmware/io.hpp"
#include "dynweigh/firmware/logbook.hpp"
#include "dynweigh/firmware/persistent_settings.hpp"
#include "dynweigh/firmware/totalizers.hpp"

namespace dynweigh::hal {

// The 10 ms tick. Lockstep boards return at once; real-time boards sleep until the next period.
class JiffyClock {
 public:
  virtual ~JiffyClock() = default;
  // Blocks until the next jiffy; false when the board is shutting down.
  virtual bool wait_next_jiffy() = 0;
  virtual std::uint32_t jiffy() const = 0;
};

// One load-cell sample per jiffy: raw counts and the converter's status bits.
class LoadCellPort {
 public:
  virtual ~LoadCellPort() = default;
  virtual firmware::LoadCellInput read_sample() = 0;
};

// The valve: a command (closed, half, open) applied `delay_100us` into the coming jiffy, and the
// position the valve reports.
class ValvePort {
 public:
  virtual ~ValvePort() = default;
  virtual void command(firmware::ValveCommand command, std::uint8_t delay_100us) = 0;
  virtual firmware::ValvePosition position() const = 0;
};

// The discharge gate under the weigh hopper: a command (closed, open) and the position its module
// reports. Optional: a board without one reports it closed and ignores the commands.
class GatePort {
 public:
  virtual ~GatePort() = default;
  virtual void command(firmware::GateCommand command) = 0;
  virtual firmware::GatePosition position() const = 0;
  // The fault bits the gate's module reports (0: none, or a module that reports none).
  virtual std::uint8_t faults() const { return 0; }
};

// The valves of a batch's ingredients 1..7 (ingredient 0's is the ValvePort), all above the one
// hopper. Optional: a board without them has ingredient 0 alone.
class IngredientValvesPort {
 public:
  virtual ~IngredientValvesPort() = default;
  // Bit i: ingredient valve i is there (bit 0, the ValvePort's, always).
  virtual std::uint8_t present() const = 0;
  // Valve `ingredient` (1..7) takes the command, every other one of them is commanded closed;
  // `ingredient` 0: all of them closed (ingredient 0's valve is the ValvePort's).
  virtual void command(std::uint8_t ingredient, firmware::ValveCommand command, std::uint8_t delay_100us) = 0;
  virtual firmware::ValvePosition position(std::uint8_t ingredient) const = 0;
};

// The serial console: a byte stream in both directions, never blocking.
class ConsolePort {
 public:
  virtual ~ConsolePort() = default;
  virtual std::size_t read(char* destination, std::size_t capacity) = 0;
  virtual void write(const char* data, std::size_t length) = 0;
  // How many bytes write() takes now without waiting and without losing any. The board drains no
  // more than this from the indicator; the rest waits in the indicator's ring (a line nobody reads
  // holds the console up, never the control loop).
  virtual std::size_t writable() const { return static_cast<std::size_t>(-1); }
};

// Marks Indicator::step alone, for a board that measures it (the Cortex-M image's instruction
// count per jiffy): called just before the step and just after it, with its outputs.
class StepProbe {
 public:
  virtual void before_step() = 0;
  virtual void after_step(const firmware::Outputs& outputs) = 0;

 protected:
  ~StepProbe() = default;
};

// Non-volatile storage for calibration and parameters.
class SettingsStore {
 public:
  virtual ~SettingsStore() = default;
  virtual bool load(firmware::PersistentSettings& settings) = 0;
  virtual bool save(const firmware::PersistentSettings& settings) = 0;
  // The logbook kept in the same memory (opened), or null: the board then keeps one in RAM.
  virtual firmware::Logbook* logbook() { return nullptr; }
  // The materials' totalizers kept in the same memory, or null: the board then counts in RAM.
  virtual firmware::TotalizerSlots* totalizers() { return nullptr; }
};

}  // namespace dynweigh::hal
