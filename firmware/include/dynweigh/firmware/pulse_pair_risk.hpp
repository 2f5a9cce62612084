#pragma once
// How far the pulse before a dose's last may aim. Aiming short of the deficit is not free when one
// pulse may still follow: what this one leaves, the last must bring, and a pulse's mass scatters
// more the more it must bring. Aiming at the whole deficit is not free either: an overfill no pulse
// takes back. This pulse's mass is taken as normal about its aim (`spread_g` its standard
// deviation), the last pulse's spread as growing in proportion to what it must bring, its mass as
// normal about that. The chance that the fill then ends beyond the class limit `limit_g`: over by
// more than the limit, or short by more than it and the last pulse misses (short by less needs no
// last pulse). The overfill's chance is exact; the last pulse's is taken at two points of what it
// must bring when it must bring more than the limit (that normal tail's mean less and plus its
// standard deviation). That is all a choice among a few aims needs (see the tests), at a fixed,
// small cost: no quadrature in a jiffy.
// The miss chance counts no time and no series. A fill left short by more than the cycle accepts
// (model_top_up_shortfall_g, 0.3 or half of the limit) waits for the last pulse's grains to land
// and be certified again: about a second. A fill left above the target by more than the class allows
// the fills' mean (a quarter of its in-service limit) is within the class itself, but moves the
// series' mean toward that limit. The pulse's aim weighs both beside the miss chance
// (top_up_pulse_law.hpp).
namespace dynweigh::firmware {

// The last pulse's standard deviation for a pulse of m grams: at_zero_g + per_g * m.
struct LastPulseSpread {
  float at_zero_g = 0.0f;
  float per_g = 0.0f;
};

float pulse_pair_miss_chance(float deficit_g, float aim_g, float spread_g, const LastPulseSpread& last,
                             float limit_g);

// Where this pulse leaves the fill, its mass normal about its aim (`left_g` the deficit less the aim,
// `spread_g` the standard deviation): the chance that it ends more than `short_g` short of the
// target, and the chance that it ends more than `over_g` above it.
float pulse_ends_short_chance(float left_g, float spread_g, float short_g);
float pulse_ends_over_chance(float left_g, float spread_g, float over_g);

}  // namespace dynweigh::firmware
