#pragma once
// The load-cell module's sample counter (docs/can-protocol.md, 0x190 bytes 4..5) as the indicator's clock on a
// link that may lose, repeat or reorder frames. One jiffy per sample:
// - the same counter again is the same sample (a duplicated frame): no jiffy, no second answer;
// - a counter a little behind the last one is a frame overtaken by a newer one: discarded, since the
//   indicator has already moved past that instant and a weight from the past must not be filtered
//   in as if it were new;
// - a counter ahead by g means g - 1 samples were lost: each becomes a jiffy without a sample (less
//   the jiffies a timer already ran for them), so the indicator's time keeps step with the plant's
//   and the supervisor's stale-sample rule counts the loss;
// - a jump outside these windows is a module that restarted or a link that was down for long: taken
//   as the new count, nothing made up.
// Freestanding (no heap, no OS): the Linux CAN board and the Cortex-M board share it.
#include <cstdint>

namespace dynweigh::hal::can {

class SampleSequence {
 public:
  // A frame at most this many samples late counts as reordered (a CAN controller's few mailboxes, a
  // driver queue); further back is a restart.
  static constexpr std::uint16_t kReorderWindow = 16;
  // At most 0.5 s of lost samples is made up with jiffies; the stale-sample fault fires after 0.1 s.
  static constexpr std::uint16_t kMaxFill = 50;

  struct Arrival {
    bool accept = false;        // run a jiffy on this sample
    std::uint16_t missing = 0;  // jiffies without a sample to run before it
  };

  Arrival arrive(std::uint16_t counter);
  // A jiffy ran without a sample (a timer stood in for a late one): one fewer to make up.
  void stood_in();
  // Forget the count (the module said it stops; the next sample starts afresh).
  void reset();

  std::uint32_t duplicates() const { return duplicates_; }
  std::uint32_t out_of_order() const { return out_of_order_; }
  std::uint32_t lost() const { return lost_; }
  std::uint32_t restarts() const { return restarts_; }

 private:
  bool started_ = false;
  std::uint16_t last_ = 0;
  std::uint32_t stood_in_ = 0;
  std::uint32_t duplicates_ = 0;
  std::uint32_t out_of_order_ = 0;
  std::uint32_t lost_ = 0;
  std::uint32_t restarts_ = 0;
};

}  // namespace dynweigh::hal::can
