#include "dynweigh/hal/linux/faulty_can_transport.hpp"

#include "dynweigh/hal/can/protocol.hpp"

namespace dynweigh::hal::linux_can {

bool FaultyCanTransport::Queue::push(const CanFrame& frame, std::uint32_t wait) {
  if (count == kQueue) return false;
  items[count++] = Held{frame, wait};
  return true;
}

CanFrame FaultyCanTransport::Queue::pop_front() {
  const CanFrame front = items[0].frame;
  for (std::size_t i = 1; i < count; ++i) items[i - 1] = items[i];
  --count;
  return front;
}

FaultyCanTransport::FaultyCanTransport(CanTransport& inner, CanFaultPlan plan)
    : inner_(inner), plan_(std::move(plan)), name_("faulty:" + inner.name()), random_(plan_.seed) {
  if (plan_.delay_frames == 0) plan_.delay_frames = 1;
}

bool FaultyCanTransport::chance(double probability) { return uniform_(random_) < probability; }

FrameFault FaultyCanTransport::decide(Direction direction, std::uint32_t index) {
  for (const ChosenFrameFault& c : plan_.chosen) {
    if (c.direction == direction && c.index == index) return c.fault;
  }
  const bool random = direction == Direction::received ? plan_.random_on_received : plan_.random_on_sent;
  if (!random) return FrameFault::none;
  // Three draws for every frame whatever the outcome: the sequence of faults depends on the seed
  // and the frame count only.
  const bool drop = chance(plan_.drop_probability);
  const bool duplicate = chance(plan_.duplicate_probability);
  const bool reorder = chance(plan_.reorder_probability);
  return drop ? FrameFault::drop : duplicate ? FrameFault::duplicate : reorder ? FrameFault::delay : FrameFault::none;
}

void FaultyCanTransport::count_down(Queue& held, Queue& ready) {
  std::size_t kept = 0;
  for (std::size_t i = 0; i < held.count; ++i) {
    Held& h = held.items[i];
    if (--h.frames_to_wait == 0 && ready.push(h.frame, 0)) continue;
    held.items[kept++] = h;
  }
  held.count = kept;
}

bool FaultyCanTransport::has_buffered_input() const { return ready_in_.count > 0 || inner_.has_buffered_input(); }

bool FaultyCanTransport::bus_off() const {
  return inner_.bus_off() || (link_fault_active_ && plan_.link_fault == LinkFault::bus_off);
}

int FaultyCanTransport::receive(CanFrame& frame, int timeout_ms) {
  for (;;) {
    if (ready_in_.count > 0) {
      frame = ready_in_.pop_front();
      return 1;
    }
    CanFrame in;
    const int got = inner_.receive(in, timeout_ms);
    if (got <= 0) return got;
    timeout_ms = 0;  // whatever happens to this frame, the caller has waited long enough
    // The bus dies right after sample link_fault_at_sample - 1: nothing of the plant's jiffy
    // link_fault_at_sample (its feedback, its heartbeats, its sample) arrives any more.
    if (plan_.link_fault != LinkFault::none && samples_ == plan_.link_fault_at_sample) link_fault_active_ = true;
    if (link_fault_active_) continue;  // a dead bus: the frame never reaches this node
    if (can::classify(in) == can::MessageKind::load_cell_sample) ++samples_;
    switch (decide(Direction::received, received_.frames++)) {
      case FrameFault::drop:
        ++received_.dropped;
        continue;
      case FrameFault::delay:
        if (held_in_.push(in, plan_.delay_frames)) {
          ++received_.delayed;
          continue;
        }
        break;
      case FrameFault::duplicate:
        if (ready_in_.push(in, 0)) ++received_.duplicated;
        break;
      case FrameFault::none:
        break;
    }
    count_down(held_in_, ready_in_);  // what was held for this frame comes right after it
    frame = in;
    return 1;
  }
}

bool FaultyCanTransport::deliver_sent(const CanFrame& frame) {
  const bool ok = inner_.send(frame);
  Queue ready;
  count_down(held_out_, ready);
  for (std::size_t i = 0; i < ready.count; ++i) inner_.send(ready.items[i].frame);
  return ok;
}

bool FaultyCanTransport::send(const CanFrame& frame) {
  if (link_fault_active_) return plan_.link_fault == LinkFault::silence;
  switch (decide(Direction::sent, sent_.frames++)) {
    case FrameFault::drop:
      ++sent_.dropped;
      return true;  // gone on the wire: the sender cannot tell
    case FrameFault::delay:
      if (held_out_.push(frame, plan_.delay_frames)) {
        ++sent_.delayed;
        return true;
      }
      return deliver_sent(frame);
    case FrameFault::duplicate:
      ++sent_.duplicated;
      return inner_.send(frame) && deliver_sent(frame);
    case FrameFault::none:
      break;
  }
  return deliver_sent(frame);
}

}  // namespace dynweigh::hal::linux_can
