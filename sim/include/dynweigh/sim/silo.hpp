#pragma once
// The silo and its orifice: Beverloo's rate through the gate's open area, scaled by the start-up
// settling alpha(t) (thesis eq. 3.16) and a seeded, correlated fluctuation (SPEC §2).
#include "dynweigh/model/beverloo.hpp"
#include "dynweigh/sim/random.hpp"
#include "dynweigh/sim/scene.hpp"

namespace dynweigh::sim {

class Silo {
 public:
  Silo(const SiloParameters& parameters, double g, std::uint64_t seed);

  // Mass that leaves over [t, t + dt] while the stroke moves linearly from `stroke_begin` to
  // `stroke_end`, and the outflow speed it leaves with. Updates alpha and the fluctuation.
  struct Outflow {
    double mass_kg;
    double speed_m_s;
  };
  Outflow discharge(double stroke_begin, double stroke_end, double dt);

  double remaining_kg() const { return remaining_kg_; }
  double alpha() const { return alpha_; }
  double full_open_rate_kg_s() const;

 private:
  double rate_at(double stroke) const;
  void update_disturbances(bool flowing, double dt);

  SiloParameters parameters_;
  model::BeverlooMaterial<double> material_;
  double g_;
  Random random_;
  double remaining_kg_;
  double alpha_;
  double fluctuation_ = 0.0;
};

}  // namespace dynweigh::sim
