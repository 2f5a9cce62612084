#include "dynweigh/firmware/fault_supervisor.hpp"

#include <cmath>

#include "dynweigh/model/beverloo.hpp"
#include "dynweigh/model/platform_frequency.hpp"

namespace dynweigh::firmware {
namespace {

constexpr float kGravity = 9.81f;

std::uint32_t jiffies_for(float ms, float jiffy_ms) {
  return std::uint32_t(std::ceil(ms / jiffy_ms));
}

}  // namespace

// The largest step the installation's own stream can put on the reading between two samples: its
// impact force (the full flow times the speed of the fall) arriving at once, on a platform that rings
// up to twice a step. The full flow is the prior's, which a density guessed 40 % low and Beverloo's
// C at the top of its range put at half the material's own. A long fall or a wide bore lands more
// than 5 % of Max at a stroke.
float FaultSupervisor::landing_step_g(const Parameters& p) {
  const float bore_m = p.get(ParameterId::bore_mm) / 1000.0f;
  const model::BeverlooMaterial<float> material{0.58f, 1.5f, 0.0005f, p.get(ParameterId::density)};
  const float flow_kg_s = model::beverloo_discharge_kg_s(material, kGravity, bore_m);
  const float speed_m_s = std::sqrt(2.0f * kGravity * p.get(ParameterId::fall_mm) / 1000.0f);
  return kLandingRingFactor * kPriorFlowShortfall * flow_kg_s * speed_m_s / kGravity * 1000.0f;
}

void FaultSupervisor::configure(const Parameters& p) {
  const float jiffy_ms = p.get(ParameterId::jiffy_ms);
  const float dead_ms = p.get(ParameterId::valve_dead_ms);
  const float stroke_ms = p.get(ParameterId::valve_stroke_ms);
  const float fall_ms = 1000.0f * std::sqrt(2.0f * p.get(ParameterId::fall_mm) / 1000.0f / kGravity);
  stale_limit_jiffies_ = jiffies_for(kStaleSampleLimitMs, jiffy_ms);
  capacity_g_ = p.get(ParameterId::capacity_g);
  outlier_bound_g_ = std::fmax(kOutlierFractionOfCapacity * capacity_g_, landing_step_g(p));
  stable_band_g_ = p.get(ParameterId::stable_band_g);
  jiffy_ms_ = jiffy_ms;
  configured_dead_ms_ = dead_ms;
  configured_shut_ms_ = dead_ms + stroke_ms;
  fall_ms_ = fall_ms;
  // New valve parameters may mean a new valve: what the feedback showed of the old one is forgotten.
  timing_.configure(jiffy_ms);
  timing_.forget();
  uncommanded_jiffies_limit_ = jiffies_for(kValveTravelFactor * configured_shut_ms_ + kValveTravelMarginMs, jiffy_ms);
  set_valve_limits(last_command_, 0.0f);
  no_flow_jiffies_ = jiffies_for(kNoFlowWindowMs, jiffy_ms);
  after_close_window_jiffies_ = jiffies_for(kFlowAfterCloseWindowMs, jiffy_ms);
  early_leak_window_jiffies_ = jiffies_for(kEarlyLeakWindowMs, jiffy_ms);
  platform_hz_ = p.get(ParameterId::platform_hz);
  platform_kg_ = p.get(ParameterId::platform_kg);
  jiffy_s_ = jiffy_ms / 1000.0f;
}

void FaultSupervisor::reset() {
  has_good_ = false;
  timing_.abandon_stroke();
  consecutive_rejected_ = 0;
  underload_samples_ = 0;
  last_command_ = ValveCommand::closed;
  command_age_ = 0;
  closed_by_dose_ = false;
  reached_closed_ = false;
  uncommanded_jiffies_ = 0;
  flow_armed_ = false;
  identical_samples_ = 0;
  history_count_ = 0;
  history_head_ = 0;
}

Fault FaultSupervisor::sample_fault(const LoadCellInput& sample) {
  if (sample.link == LinkStatus::bus_off) return Fault::bus_off;
  if (sample.status & kLoadCellAdcError) return Fault::adc_error;
  if (sample.status & kLoadCellOverload) return Fault::overload;
  if (sample.status & kLoadCellUnderload) return Fault::underload;
  return Fault::none;
}

Fault FaultSupervisor::watch_link(const LoadCellInput& sample) {
  const Fault bus = sample.link == LinkStatus::bus_off ? Fault::bus_off : Fault::none;
  if (sample.fresh) {
    stale_jiffies_ = 0;
    silent_jiffies_ = 0;
    return bus;
  }
  // A whole stale window in which the board heard nothing at all is the bus, not the load cell.
  silent_jiffies_ = sample.link == LinkStatus::silent ? silent_jiffies_ + 1 : 0;
  if (++stale_jiffies_ < stale_limit_jiffies_ || bus != Fault::none) return bus;
  return silent_jiffies_ >= stale_limit_jiffies_ ? Fault::can_silence : Fault::stale_sample;
}

// A stream that lands as one slug on a stiff, lightly damped platform swings it above its empty
// weight, for part of each period of its ringing, by more than the cell's range below zero: the
// installation's own landing, while a dose runs. A lifted platform or a cut wire stays there.
Fault FaultSupervisor::watch_underload(const LoadCellInput& sample, float gross_g, bool dose_running) {
  if (!(sample.status & kLoadCellUnderload)) {
    underload_samples_ = 0;
    return Fault::none;
  }
  ++underload_samples_;
  if (!dose_running || !(platform_hz_ > 0.0f)) return Fault::underload;
  const float load_kg = gross_g > 0.0f ? gross_g / 1000.0f : 0.0f;
  return float(underload_samples_) > ring_crest_samples(load_kg) ? Fault::underload : Fault::none;
}

// How many samples a live reading can spend at one crest of the platform's ringing under `load_kg`:
// about half a period, and two more.
float FaultSupervisor::ring_crest_samples(float load_kg) const {
  const auto ringing = model::platform_ringing(platform_hz_, 0.0f, platform_kg_, load_kg);
  return std::ceil(float(M_PI) / (ringing.omega_rad_s * jiffy_s_)) + 2.0f;
}

Fault FaultSupervisor::watch_sample(const LoadCellInput& sample, bool weighed, float gross_g, bool dose_running) {
  const Fault link = watch_link(sample);
  if (link != Fault::none || !sample.fresh) return link;
  const Fault underload = watch_underload(sample, weighed ? gross_g : 0.0f, dose_running);
  const Fault own = sample_fault(sample);
  if (own != Fault::none && own != Fault::underload) return own;
  if (underload != Fault::none) return underload;
  if (screen_fault_ != Fault::none) return screen_fault_;
  if (weighed && gross_g > capacity_g_ + kOverloadMarginG) return Fault::overload;
  return Fault::none;
}

float FaultSupervisor::screen_sample(float raw_counts, float counts_per_gram, bool strict, Fault& fault) {
  fault = Fault::none;
  const float bound_counts = outlier_bound_g_ * counts_per_gram;
  if (!has_good_ || !(bound_counts > 0.0f) || std::fabs(raw_counts - good_counts_) <= bound_counts) {
    has_good_ = true;
    good_counts_ = raw_counts;
    consecutive_rejected_ = 0;
    return raw_counts;
  }
  ++rejected_total_;
  ++consecutive_rejected_;
  const bool consistent = consecutive_rejected_ >= 2 && std::fabs(raw_counts - last_rejected_counts_) <= bound_counts;
  last_rejected_counts_ = raw_counts;
  if (strict) {
    if (consecutive_rejected_ >= kOutlierFaultCount) fault = Fault::sample_jump;
    return good_counts_;
  }
  if (consistent) {  // a new level held for two samples: a load placed or taken off
    good_counts_ = raw_counts;
    consecutive_rejected_ = 0;
  }
  return good_counts_;
}

Fault FaultSupervisor::watch(const Observation& o) {
  const Fault valve = watch_valve(o);
  if (valve != Fault::none) timing_.abandon_stroke();  // a stroke that faulted times no healthy valve
  const Fault flow = watch_flow(o);
  const Fault after = watch_after_close(o);
  return valve != Fault::none ? valve : flow != Fault::none ? flow : after;
}

namespace {
bool p_is_closed(ValvePosition p) { return p == ValvePosition::closed; }
}  // namespace

// The slower of the datasheet's and the measured time from a command to a shut (or open) valve.
float FaultSupervisor::valve_shut_ms() const {
  using D = ValveTimingMonitor::Direction;
  const float measured = std::fmax(timing_.slowest_arrival_ms(D::opening), timing_.slowest_arrival_ms(D::closing));
  return std::fmax(configured_shut_ms_, measured);
}

float FaultSupervisor::dead_time_to_keep_ms() const {
  using D = ValveTimingMonitor::Direction;
  const float seen_ms = std::fmax(timing_.slowest_dead_ms(D::opening), timing_.slowest_dead_ms(D::closing));
  const bool memory_full = timing_.dead_times(D::opening) >= ValveTimingMonitor::kMemory ||
                           timing_.dead_times(D::closing) >= ValveTimingMonitor::kMemory;
  return memory_full ? seen_ms : std::fmax(seen_ms, learned_dead_ms_);
}

// How long the command just given may take: to leave the end position, to reach the new one.
void FaultSupervisor::set_valve_limits(ValveCommand command, float delay_ms) {
  using D = ValveTimingMonitor::Direction;
  const D own = command == ValveCommand::open ? D::opening : D::closing;
  const D other = own == D::opening ? D::closing : D::opening;
  float leave_ms = 0.0f, arrival_ms = 0.0f;
  if (timing_.strokes(own) > 0) {
    leave_ms = timing_.slowest_leave_ms(own) + kValveLeaveMarginMs;
    const float slowest = timing_.slowest_arrival_ms(own);
    arrival_ms = slowest + kValveArrivalMarginMs + kValveArrivalMarginFraction * slowest;
  } else if (timing_.strokes(other) > 0) {
    // Never seen this way: for the stroke, which often differs between the ways, the generous
    // travel limit; the other way's dead time if its feedback showed one (`moving` before the end
    // position: one actuator, one supply), else the travel limit too.
    const float other_arrival_ms = timing_.slowest_arrival_ms(other);
    arrival_ms = kValveTravelFactor * other_arrival_ms + kValveTravelMarginMs;
    const bool dead_time_seen = timing_.slowest_leave_ms(other) < other_arrival_ms;
    leave_ms = dead_time_seen ? timing_.slowest_leave_ms(other) + kValveLeaveMarginMs : arrival_ms;
  } else {
    // No full stroke seen (a valve found open, feedback that echoes the command, a dose that closed
    // before the valve was open): the datasheet's travel.
    arrival_ms = kValveTravelFactor * configured_shut_ms_ + kValveTravelMarginMs;
    leave_ms = configured_dead_ms_ + kValveLeaveMarginMs;
  }
  // A dead time the feedback has shown on any stroke from standstill (closed to half, a close given
  // before the valve was open) is this valve's, whatever the datasheet says: the slowest either way
  // (one actuator, one supply), so that one fast stroke one way does not set the next one's limit.
  // The slowest the material's doses showed before a restart counts as seen, no longer than a
  // healthy valve takes to shut: after a restart the supervisor has timed one opening at most, and a
  // valve whose dead time jitters by 15 % can show it 2.5 sigmas short (50 ms of a 78 ms valve), less
  // than the close that follows takes to leave `open`, 40 ms margin and all.
  const float kept_dead_ms = std::fmin(learned_dead_ms_, valve_shut_ms());
  const float slowest_dead_ms =
      std::fmax(std::fmax(timing_.slowest_dead_ms(own), timing_.slowest_dead_ms(other)), kept_dead_ms);
  if (slowest_dead_ms > 0.0f) {
    leave_ms = slowest_dead_ms + kValveLeaveMarginMs;
    arrival_ms = std::fmax(arrival_ms, leave_ms + kValveArrivalMarginMs);
  }
  valve_start_jiffies_ = jiffies_for(leave_ms + delay_ms, jiffy_ms_);
  valve_travel_jiffies_ = jiffies_for(arrival_ms + delay_ms, jiffy_ms_);
  const float shut_ms = valve_shut_ms() + delay_ms;
  rest_jiffies_ = jiffies_for(shut_ms + fall_ms_ + kRestMarginMs, jiffy_ms_);
  early_leak_jiffies_ = jiffies_for(shut_ms + fall_ms_ + kEarlyLeakMarginMs, jiffy_ms_);
}

// A dose's valve had a chance to deliver once its feedback reported it open (or at the half the
// fine feed asks for), or, where the feedback shows nothing, once it was commanded open for the
// slower of the datasheet's and the measured time to open. Feedback that showed it moving and
// never there is a valve still opening when the close came, however long the datasheet's time:
// a slow valve's first tenths of a second, before coarse grains pass the gate, let next to nothing
// through.
void FaultSupervisor::follow_dose_opening(const Observation& o) {
  if (!o.dose_running) {
    dose_open_jiffies_ = 0;
    dose_valve_opened_ = false;
    dose_valve_moving_seen_ = false;
    last_opening_reached_open_ = false;
    return;
  }
  if (o.command_in_force == ValveCommand::closed) return;
  if (last_command_ == ValveCommand::closed) last_opening_reached_open_ = false;  // a new opening
  if (dose_open_jiffies_ < 0xFFFFFFFFu) ++dose_open_jiffies_;
  if (o.position == ValvePosition::open || o.position == ValvePosition::half) {
    dose_valve_opened_ = true;
    last_opening_reached_open_ = true;
  }
  if (o.position == ValvePosition::moving) dose_valve_moving_seen_ = true;
}

bool FaultSupervisor::dose_valve_could_deliver() const {
  if (dose_valve_opened_) return true;
  if (dose_valve_moving_seen_) return false;
  return float(dose_open_jiffies_) * jiffy_ms_ >= valve_shut_ms();
}

Fault FaultSupervisor::watch_valve(const Observation& o) {
  timing_.observe(o.command_in_force, o.command_delay_ms, o.position);
  follow_dose_opening(o);
  if (o.command_in_force != last_command_) {
    closed_by_dose_ = o.command_in_force == ValveCommand::closed && o.dose_running;
    last_command_ = o.command_in_force;
    command_age_ = 0;
    open_reference_g_ = o.filtered_g;
    reached_closed_ = false;
    uncommanded_jiffies_ = 0;
    set_valve_limits(o.command_in_force, o.command_delay_ms);
  }
  if (command_age_ < 0xFFFFFFFFu) ++command_age_;
  // Feedback that reads closed while the weight rises is wrong or absent (an open-loop replay, a
  // board without the valve module's frame), not a closed valve: the flow rules watch that case.
  // A closed valve is only stuck once the stream had time to land and nothing did.
  const float rise_g = std::fmax(kNoFlowRiseMinG, kNoFlowRiseFractionOfCapacity * capacity_g_);
  const bool flow_seen = o.filtered_g >= open_reference_g_ + rise_g;
  const bool closed_too_long = p_is_closed(o.position) && command_age_ >= rest_jiffies_ && !flow_seen;
  const bool started = command_age_ >= valve_start_jiffies_;
  const bool travelled = command_age_ >= valve_travel_jiffies_;
  if (travelled) timing_.abandon_stroke();
  const ValvePosition p = o.position;
  switch (o.command_in_force) {
    case ValveCommand::closed:
      if (p == ValvePosition::closed) {
        reached_closed_ = true;
        uncommanded_jiffies_ = 0;
        break;
      }
      if (!reached_closed_) {  // it never closed after the close: stuck open
        if (started && (p == ValvePosition::open || p == ValvePosition::half)) return Fault::valve_stuck_open;
        if (travelled) return Fault::valve_stuck_open;
        break;
      }
      // Closed, then reporting movement with no command. Given the travel limit, since the feedback
      // can arrive ahead of a command given in the same jiffy (open-loop replays of recorded valves).
      if (++uncommanded_jiffies_ >= uncommanded_jiffies_limit_) return Fault::valve_stuck_open;
      break;
    case ValveCommand::open:
      if (closed_too_long) return Fault::valve_stuck_closed;
      if (travelled && p != ValvePosition::open && p != ValvePosition::closed) return Fault::valve_stuck_closed;
      break;
    case ValveCommand::half:
      if (closed_too_long) return Fault::valve_stuck_closed;
      if (started && p == ValvePosition::open) return Fault::valve_stuck_open;
      if (travelled && p != ValvePosition::half && p != ValvePosition::closed) {
        return p == ValvePosition::open ? Fault::valve_stuck_open : Fault::valve_stuck_closed;
      }
      break;
  }
  return Fault::none;
}

Fault FaultSupervisor::watch_flow(const Observation& o) {
  if (!o.dose_flowing || o.command_in_force == ValveCommand::closed) {
    flow_armed_ = false;
    return Fault::none;
  }
  if (!flow_armed_) {
    flow_armed_ = true;
    flow_reference_g_ = o.filtered_g;
    flow_reference_age_ = 0;
    identical_samples_ = 0;
    history_count_ = 0;
    history_head_ = 0;
    last_raw_counts_ = o.raw_counts;
  }
  // no_flow: the weight must keep rising while the dose's valve is open.
  const float rise_g = std::fmax(kNoFlowRiseMinG, kNoFlowRiseFractionOfCapacity * capacity_g_);
  ++flow_reference_age_;
  if (o.filtered_g >= flow_reference_g_ + rise_g) {
    flow_reference_g_ = o.filtered_g;
    flow_reference_age_ = 0;
  }
  if (flow_reference_age_ >= no_flow_jiffies_) return Fault::no_flow;

  // sensor_frozen: identical raw counts while the recent flow would have moved them by many counts.
  const float oldest_g = history_count_ == kHistory ? history_[history_head_] : o.filtered_g;
  history_[history_head_] = o.filtered_g;
  history_head_ = (history_head_ + 1) % kHistory;
  if (history_count_ < kHistory) ++history_count_;
  if (!o.fresh_sample) return Fault::none;
  identical_samples_ = o.raw_counts == last_raw_counts_ ? identical_samples_ + 1 : 0;
  last_raw_counts_ = o.raw_counts;
  if (history_count_ < kHistory) return Fault::none;
  // Falling counts are as live as rising ones: a two-stage feed's reading dips when the reduced
  // stream lands, and a sensor that freezes there must not wait for no_flow's two seconds.
  const float rate_counts = std::fabs(o.filtered_g - oldest_g) * o.counts_per_gram / float(kHistory);
  if (!(rate_counts > 0.0f)) return Fault::none;
  float needed = std::fmax(float(kFrozenMinSamples), std::ceil(kFrozenMinCounts / rate_counts));
  // At a crest of the platform's ringing the flow's rise and the ring's fall cancel for a few
  // samples: a live sensor can sit still there for up to about half a period.
  if (platform_hz_ > 0.0f) needed = std::fmax(needed, ring_crest_samples(o.filtered_g / 1000.0f));
  if (float(identical_samples_ + 1) >= needed) return Fault::sensor_frozen;
  return Fault::none;
}

bool FaultSupervisor::watch_early_leak(float mean_g, float filtered_g, float rise_g) {
  if (command_age_ <= early_leak_jiffies_) return false;
  const std::uint32_t into = command_age_ - early_leak_jiffies_ - 1;
  const std::uint32_t window = into / early_leak_window_jiffies_;
  if (window > 1) return false;
  if (into == 0) {
    early_leak_sums_g_[0] = early_leak_sums_g_[1] = 0.0f;
    early_leak_low_g_ = early_leak_high_g_ = filtered_g;
  }
  early_leak_sums_g_[window] += mean_g;
  early_leak_low_g_ = std::fmin(early_leak_low_g_, filtered_g);
  early_leak_high_g_ = std::fmax(early_leak_high_g_, filtered_g);
  if (into + 1 != 2 * early_leak_window_jiffies_) return false;
  const float risen_g = (early_leak_sums_g_[1] - early_leak_sums_g_[0]) / float(early_leak_window_jiffies_);
  return risen_g > rise_g && risen_g > kEarlyLeakShareOfRange * (early_leak_high_g_ - early_leak_low_g_);
}

Fault FaultSupervisor::watch_after_close(const Observation& o) {
  if (!closed_by_dose_ || o.command_in_force != ValveCommand::closed) return Fault::none;
  if (command_age_ == 1) {
    const std::uint32_t least = jiffies_for(kLeastRingWindowMs, jiffy_ms_);
    const std::uint32_t period = ring_period_jiffies(o.filtered_g);
    settled_weight_.reset(period > least ? period : least);
  }
  settled_weight_.push(o.filtered_g);
  const float weight_g = settled_weight_.mean();
  const float rise_g = std::fmax(kFlowAfterCloseRiseStableBands * stable_band_g_,
                                 kFlowAfterCloseRiseFractionOfCapacity * capacity_g_);
  if (watch_early_leak(weight_g, o.filtered_g, rise_g)) return Fault::flow_after_close;
  if (command_age_ == rest_jiffies_) {
    const std::uint32_t period = ring_period_jiffies(o.filtered_g);
    const std::uint32_t whole = period > 0 ? PeriodMean::kCapacity / period : 0;
    late_window_jiffies_ = whole > 0 ? whole * period : PeriodMean::kCapacity;
    settled_weight_.reset(late_window_jiffies_);
    settled_weight_.push(o.filtered_g);
  }
  const std::uint32_t reference_age = rest_jiffies_ + late_window_jiffies_;
  if (command_age_ == reference_age) after_close_reference_g_ = settled_weight_.mean();
  if (command_age_ <= reference_age || command_age_ > reference_age + after_close_window_jiffies_) {
    return Fault::none;
  }
  return settled_weight_.mean() > after_close_reference_g_ + rise_g ? Fault::flow_after_close : Fault::none;
}

// One period of the platform's ringing under the load on it, in jiffies (1 for a rigid scale).
std::uint32_t FaultSupervisor::ring_period_jiffies(float net_g) const {
  if (!(platform_hz_ > 0.0f)) return 1;
  const auto ringing = model::platform_ringing(platform_hz_, 0.0f, platform_kg_, net_g / 1000.0f);
  return std::uint32_t(std::lround(2.0f * float(M_PI) / (ringing.omega_rad_s * jiffy_s_)));
}

}  // namespace dynweigh::firmware
