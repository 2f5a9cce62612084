#pragma once
// What a top-up pulse's certified mass says of the pulse. The scale saw less of it than a small share
// of what it should have delivered (at least a gram): it moved nothing, as a frozen reading or an
// empty silo would show it, and no further pulse is given on that (a valve slower than its datasheet
// lets through far less than expected, but not nothing). A sized pulse shorter than the valve's
// travel to the position it was sent to may move nothing of itself: the valve's timing jitter (the
// open and the close command each have their own) may close it before the gate parts, or the grains
// arch over the slit. That is a lesson for the pulse law (the next pulse is longer), not a reason to
// stop.
namespace dynweigh::firmware {

enum class PulseVerdict {
  delivered,          // the law learns what it delivered
  parted_too_little,  // nothing, from a sized pulse too short to part the gate: the law learns that
  moved_nothing,      // nothing: the top-up ends with the result as it is
};

// `travel_s`: the valve's travel from closed to the pulse's position (0: not known). `sized`: the pulse
// was sized by the pulse law (a baseline's fixed pulse teaches nothing either way).
PulseVerdict judge_pulse(float expected_g, float delivered_g, float pulse_s, float travel_s, bool sized);

}  // namespace dynweigh::firmware
