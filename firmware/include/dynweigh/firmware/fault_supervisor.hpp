#pragma once
// Watches the link, the load cell, the valve and the flow once per jiffy and names what broke.
// The Indicator raises what it reports: the valve closes in the same jiffy, the fault latches.
//
// - The link and the load cell's own word: `bus_off` as the board reports it; no sample for
//   kStaleSampleLimitMs (fault.hpp) is `stale_sample`, or `can_silence` when the board heard nothing
//   at all on the bus for as long; a sample's status bits are `adc_error`, `overload`, `underload`
//   (during a dose, once it outlasts half a period of the platform's ringing + 2 samples: a hard
//   landing swings a stiff platform above its empty weight for part of each period);
//   a calibrated gross weight more than kOverloadMarginG above Max is `overload` too.
// - Outliers: a sample further than kOutlierFractionOfCapacity x Max from the last good one moved
//   faster than anything on the scale can: the largest physical step is the stream's impact
//   (about 1.2 kg for the 60 mm bore falling 1.2 m, 2.4 kg/s x 4.9 m/s) and the 12 Hz platform
//   swings on it by at most F x omega x jiffy (about 0.9 kg per 10 ms), well inside 5 % of 50 kg.
//   Where the installation's parameters say its stream lands harder (a wide bore, a long fall:
//   twice the prior flow's impact force, as a lightly damped platform swings to twice a step), that
//   is the limit instead.
//   Such a sample is rejected and the last good value held. While a dose runs, kOutlierFaultCount
//   in a row raise `sample_jump`; otherwise two consistent samples confirm a new level (a load
//   placed on the scale), taken one jiffy late.
// - Valve feedback against the command, judged by the timing this valve's feedback has shown
//   (valve_timing.hpp: for opening and closing apart, the slowest of the last 8 full strokes, from
//   the command to the feedback's leaving its end position and to its reporting the new one).
//   Closing (or going to half) from open, a valve still reporting open kValveLeaveMarginMs after the
//   slowest leave seen, or not closed kValveArrivalMarginMs plus kValveArrivalMarginFraction after
//   the slowest arrival seen: `valve_stuck_open`. That is within 100 ms of the moment this valve,
//   healthy, would have shut. A direction not yet seen is judged by the other direction's leave (if
//   its feedback showed `moving`), and by the travel limit for the arrival: kValveTravelFactor x the
//   other direction's arrival + kValveTravelMarginMs. With no stroke seen at all (a valve found
//   open, feedback that echoes the command) the datasheet's: its dead time + kValveLeaveMarginMs to
//   leave, and the travel limit on its dead time plus stroke. A dead time the feedback showed on
//   any stroke from standstill (closed to half, an opening closed before it was open) replaces the
//   leave limit: the slowest seen + kValveLeaveMarginMs; so does the slowest one the material's
//   doses showed before a restart (kept in the settings: expect_dead_time_ms). Opening, a valve
//   still reporting closed once the stream had time to land (the slower of the configured and the
//   measured timing, the fall, a second) while the weight did not rise, or stuck mid-stroke past the
//   arrival limit: `valve_stuck_closed`. Feedback reading closed while the weight rises is taken as
//   missing feedback (open-loop replays), not a fault. A valve that closed and then reports moving
//   with no command is stuck open after the travel limit.
// - `no_flow`: a dose's valve open and the filtered weight not rising by kNoFlowRise within 2 s
//   (at the start or later: a silo run empty). dose_valve_could_deliver() tells the dosing cycle
//   whether a dose that certified next to nothing had its valve open at all (feedback at open or
//   half, or, where the feedback never showed it moving, commanded open for the slower valve
//   time): only then is it `no_flow`.
// - `sensor_frozen`: the raw counts identical for several samples while a dose's flow runs at a
//   rate that moves them by many counts in that time, and for longer than half a period of the
//   platform (`platform_hz`): at a crest of its ringing a live reading can stand still that long.
// - `flow_after_close`: after a dose's close, once dead time, stroke, the stream's fall time and a
//   margin have passed, the filtered weight still rises by more than kFlowAfterCloseRise within 2 s;
//   and a fast leak sooner: after a short margin, the mean over 250 ms above the mean over the 250 ms
//   before by kFlowAfterCloseRise and by a share of the range the reading covered over both (a
//   ringing swings more than it rises), before a stuck valve can run the silo empty while the long
//   margin passes. Both watch the filtered weight averaged over the platform's ringing: a loaded
//   platform rings slowly and long, and through the filter alone its swing can exceed the rise. The
//   early one over one period (0.5 s at least: its mean must not still hold the landing); the later
//   one, from the margin on, over as many periods as fill the mean's buffer, compared from when that
//   is full: a platform left at the default `platform_hz` may ring at 2 to 3 Hz, and one period's
//   mean of the wrong length keeps a fifth of the swing.
#include <cstdint>

#include "dynweigh/firmware/fault.hpp"
#include "dynweigh/firmware/io.hpp"
#include "dynweigh/firmware/parameters.hpp"
#include "dynweigh/firmware/period_mean.hpp"
#include "dynweigh/firmware/valve_timing.hpp"

namespace dynweigh::firmware {

class FaultSupervisor {
 public:
  static constexpr float kOutlierFractionOfCapacity = 0.05f;
  static constexpr std::uint32_t kOutlierFaultCount = 3;
  static constexpr float kLandingRingFactor = 2.0f;  // a step on a lightly damped platform swings to 2x
  static constexpr float kPriorFlowShortfall = 2.0f;  // the material's full flow, at most, over the prior's
  static constexpr float kValveLeaveMarginMs = 40.0f;    // dead-time jitter, a feedback frame late
  static constexpr float kValveArrivalMarginMs = 30.0f;
  static constexpr float kValveArrivalMarginFraction = 0.05f;
  static constexpr float kValveTravelFactor = 3.0f;      // x (dead time + stroke): a slow valve passes
  static constexpr float kValveTravelMarginMs = 100.0f;
  static constexpr float kNoFlowWindowMs = 2000.0f;
  static constexpr float kNoFlowRiseFractionOfCapacity = 0.0002f;  // 10 g on 50 kg
  static constexpr float kNoFlowRiseMinG = 5.0f;
  static constexpr float kFrozenMinCounts = 10.0f;       // the flow would have moved this many counts
  static constexpr std::uint32_t kFrozenMinSamples = 5;
  static constexpr float kRestMarginMs = 1000.0f;   // the display filter's ringing after the landing
  static constexpr float kFlowAfterCloseWindowMs = 2000.0f;
  static constexpr float kEarlyLeakMarginMs = 400.0f;  // the 2 Hz filter's lag has decayed to ~4 %
  static constexpr float kEarlyLeakWindowMs = 250.0f;
  // A leak rises through both windows: the second's mean above the first's by half the range the
  // filtered weight covered there (a steady flow), less what ringing adds to the range. A ringing the
  // mean over the predicted period did not cancel (a soft platform left at its default
  // `platform_hz`) swings the range far more than the two means apart; the early check then leaves
  // the rise to the later one.
  static constexpr float kEarlyLeakShareOfRange = 0.35f;
  static constexpr float kFlowAfterCloseRiseFractionOfCapacity = 0.002f;  // 100 g on 50 kg; settling rings +-30 g
  static constexpr float kFlowAfterCloseRiseStableBands = 50.0f;
  // The after-close checks average the weight over at least this long, whatever `platform_hz` says:
  // a loaded platform whose parameters were left at their defaults may ring at 2 Hz, and a mean over
  // the configured (shorter) period passes most of its swing.
  static constexpr float kLeastRingWindowMs = 500.0f;
  static constexpr float kOverloadMarginG = 9.0f;  // 9 d above Max, as OIML R76 blanks

  // Limits from the installation's parameters (capacity, jiffy, valve timing, fall height).
  void configure(const Parameters& parameters);
  // Forget all history of valve, flow and outliers (a new zero, and `clearfault`).
  void reset();
  // `clearfault`: reset(), and the stale sample's count starts again.
  void clear() {
    stale_jiffies_ = 0;
    reset();
  }

  // The jiffy's sample, after the scale took it (screen_sample, the filter): its link, its status
  // bits, its screen and, where the scale is calibrated (`weighed`), the gross weight it shows.
  // Fault::none, or the first thing found wrong.
  // `dose_running`: a dose's stream may be landing, and its impact ringing the platform.
  Fault watch_sample(const LoadCellInput& sample, bool weighed, float gross_g, bool dose_running = false);
  // What a fresh sample says of itself (bus-off, its status bits), counting nothing.
  static Fault sample_fault(const LoadCellInput& sample);
  // Every jiffy since the last fresh sample brought one (or `clearfault` was given since).
  bool sample_current() const { return stale_jiffies_ == 0; }
  // No sample for the stale limit: the reading shows nothing.
  bool sample_stale() const { return stale_jiffies_ >= stale_limit_jiffies_; }

  // The outlier screen: the counts to use this jiffy (the sample, or the last good one held).
  // `strict` while a dose runs; `fault` is set to sample_jump when the rejections persist.
  float screen_sample(float raw_counts, float counts_per_gram, bool strict, Fault& fault);
  float screen_sample(float raw_counts, float counts_per_gram, bool strict) {
    return screen_sample(raw_counts, counts_per_gram, strict, screen_fault_);
  }
  std::uint32_t rejected_samples() const { return rejected_total_; }
  // What the valve's feedback has shown of its timing (the model cutoff times its close with it).
  const ValveTimingMonitor& valve_timing() const { return timing_; }
  // Another valve takes over (a batch's next ingredient): the timing the feedback showed is the last
  // one's. The watch in force (the last close's) keeps its limits; the next command sets new ones.
  void another_valve() { timing_.forget(); }
  // Before a dose: the dead time the material's earlier doses measured of this valve (kept in the
  // settings), ms; 0 for none. It counts as a dead time seen: a restart forgets the strokes timed
  // since the power-up, not what the material kept (see set_valve_limits).
  void expect_dead_time_ms(float dead_ms) { learned_dead_ms_ = dead_ms > 0.0f && dead_ms < 1000.0f ? dead_ms : 0.0f; }
  // After a dose: the dead time the material should keep. The slowest the feedback showed since the
  // power-up once it has timed a full memory of strokes one way (it follows the valve as it ages or
  // is serviced); until then the slower of that and the one kept (a few strokes say little of the
  // valve's slowest). 0: none.
  float dead_time_to_keep_ms() const;

  // Whether the running dose's valve was open long enough to deliver: if not, a dose that closed
  // before its valve opened delivered nothing through no fault of the plant (no `no_flow`).
  bool dose_valve_could_deliver() const;
  // Whether the feedback showed the valve open (or at half) since the running dose's last opening
  // command: a top-up pulse that did see it there and moved the scale by nothing met an empty silo.
  bool last_opening_reached_open() const { return last_opening_reached_open_; }

  // What the supervisor needs to know about one jiffy, after the sample was processed.
  struct Observation {
    ValveCommand command_in_force = ValveCommand::closed;  // the command sent last jiffy
    float command_delay_ms = 0.0f;  // how far into its jiffy that command acted (the delay byte)
    ValvePosition position = ValvePosition::closed;        // the valve's feedback now
    bool dose_flowing = false;    // a dose is in its dosing phase
    bool dose_running = false;    // a dose is dosing or settling
    bool fresh_sample = false;
    float raw_counts = 0.0f;      // the sample as it arrived
    float counts_per_gram = 1.0f;
    float filtered_g = 0.0f;
  };
  // Fault::none, or the first thing found wrong this jiffy.
  Fault watch(const Observation& o);

 private:
  static float landing_step_g(const Parameters& p);
  Fault watch_link(const LoadCellInput& sample);
  Fault watch_underload(const LoadCellInput& sample, float gross_g, bool dose_running);
  float ring_crest_samples(float load_kg) const;
  Fault watch_valve(const Observation& o);
  void follow_dose_opening(const Observation& o);
  void set_valve_limits(ValveCommand command, float delay_ms);
  float valve_shut_ms() const;
  Fault watch_flow(const Observation& o);
  bool watch_early_leak(float mean_g, float filtered_g, float rise_g);
  Fault watch_after_close(const Observation& o);

  // Limits.
  float capacity_g_ = 50000.0f;
  float outlier_bound_g_ = 2500.0f;  // the outlier screen's step, grams
  float stable_band_g_ = 1.0f;
  float jiffy_ms_ = 10.0f;
  float configured_dead_ms_ = 30.0f;   // the datasheet's
  float configured_shut_ms_ = 110.0f;  // the datasheet's dead time and stroke
  float learned_dead_ms_ = 0.0f;       // the material's kept dead time: expect_dead_time_ms()
  float fall_ms_ = 495.0f;
  std::uint32_t valve_start_jiffies_ = 43;   // for the command in force: leave its end position by
  std::uint32_t valve_travel_jiffies_ = 43;  // ... and reach the new one by
  std::uint32_t uncommanded_jiffies_limit_ = 43;
  std::uint32_t no_flow_jiffies_ = 200;
  std::uint32_t rest_jiffies_ = 111;
  std::uint32_t after_close_window_jiffies_ = 200;
  std::uint32_t early_leak_jiffies_ = 71;
  std::uint32_t early_leak_window_jiffies_ = 20;

  // Link.
  std::uint32_t stale_limit_jiffies_ = 10;
  std::uint32_t stale_jiffies_ = 0;   // jiffies without a sample
  std::uint32_t silent_jiffies_ = 0;  // of those, jiffies the link reported silent

  // Outlier screen.
  Fault screen_fault_ = Fault::none;  // the last screen's
  bool has_good_ = false;
  float good_counts_ = 0.0f;
  float last_rejected_counts_ = 0.0f;
  std::uint32_t consecutive_rejected_ = 0;
  std::uint32_t underload_samples_ = 0;  // fresh samples in a row with the underload bit
  std::uint32_t rejected_total_ = 0;

  // Valve.
  ValveTimingMonitor timing_;
  ValveCommand last_command_ = ValveCommand::closed;
  std::uint32_t command_age_ = 0;  // jiffies since the command in force was first seen
  bool closed_by_dose_ = false;    // the close in force ended a dose's flow
  float open_reference_g_ = 0.0f;  // the weight when the command in force was given
  bool reached_closed_ = false;    // the close in force was seen through to `closed`
  std::uint32_t uncommanded_jiffies_ = 0;  // reported moving since, with no new command
  std::uint32_t dose_open_jiffies_ = 0;    // the running dose's valve commanded open (or half)
  bool dose_valve_opened_ = false;         // ... and its feedback reported it there
  bool dose_valve_moving_seen_ = false;    // ... or reported it on its way there
  bool last_opening_reached_open_ = false; // the latest opening command's feedback at open or half

  // Flow.
  bool flow_armed_ = false;
  float flow_reference_g_ = 0.0f;
  std::uint32_t flow_reference_age_ = 0;
  float last_raw_counts_ = 0.0f;
  std::uint32_t identical_samples_ = 0;
  float platform_hz_ = 12.0f;
  float platform_kg_ = 4.0f;
  float jiffy_s_ = 0.01f;
  static constexpr std::uint32_t kHistory = 32;  // filtered weights of the last jiffies: the recent rate
  float history_[kHistory] = {};
  std::uint32_t history_head_ = 0;
  std::uint32_t history_count_ = 0;

  // After close: the filtered weight averaged over one period of the platform's ringing.
  std::uint32_t ring_period_jiffies(float net_g) const;
  PeriodMean settled_weight_;
  float after_close_reference_g_ = 0.0f;
  std::uint32_t late_window_jiffies_ = 1;  // the later check's mean, whole predicted periods
  float early_leak_sums_g_[2] = {};  // the period's mean summed over the two windows
  float early_leak_low_g_ = 0.0f;    // the filtered weight's lowest and highest there
  float early_leak_high_g_ = 0.0f;
};

}  // namespace dynweigh::firmware
