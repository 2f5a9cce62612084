#pragma once
// How much of a flow's fluctuation survives in its mean over a window. The material in flight at a
// close left the orifice over the last flight time T; a flow fluctuating about its mean with rms
// sigma and correlation time tau (an Ornstein-Uhlenbeck process, as the simulator's silo draws it)
// has a mean over T of rms sigma * share, with
//   share^2 = 2 r (1 - r (1 - exp(-1/r))),  r = tau / T,
// 1 for a window short against tau, sqrt(2 tau / T) for a long one (docs/physics.md, The flow's
// fluctuation).
#include <cmath>

namespace dynweigh::model {

// A window of no length keeps the whole fluctuation; an uncorrelated one averages out entirely.
template <typename Scalar>
Scalar fluctuation_share_of_window_mean(Scalar correlation_s, Scalar window_s) {
  if (!(window_s > Scalar(0))) return Scalar(1);
  if (!(correlation_s > Scalar(0))) return Scalar(0);
  const Scalar r = correlation_s / window_s;
  // For a window far shorter than tau the closed form cancels to nothing in float: its series.
  const Scalar x = Scalar(1) / r;
  const Scalar squared = r > Scalar(10) ? Scalar(1) - x / Scalar(3) + x * x / Scalar(12) - x * x * x / Scalar(60)
                                        : Scalar(2) * r * (Scalar(1) - r * (Scalar(1) - std::exp(-x)));
  return squared > Scalar(0) ? (squared < Scalar(1) ? std::sqrt(squared) : Scalar(1)) : Scalar(0);
}

}  // namespace dynweigh::model
