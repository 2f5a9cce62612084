#!/usr/bin/env python3
"""The outside plant's physics on its own, against the textbook: mass conservation, Beverloo's
flow, the impact force of a steady stream, the corrected sign of the close-instant excess
(reading - final = mdot v0 / g, not minus), the fall time, the platform's frequency against its
moving mass, the valve's dead time, stroke and feedback, and the load cell's int32 range."""
import math
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from outside_plant import (G, INT32_MAX, STATUS_OVERLOAD, STEP_S, Physics, PlantConfig,  # noqa: E402
                           open_area_fraction)


def beverloo(config):
    """W = C rho_b sqrt(g) (D - k d)^(5/2), written out here rather than taken from the plant."""
    return config.beverloo_c * config.density * math.sqrt(G) * (
        config.bore_mm / 1000.0 - config.beverloo_k * config.grain_mm / 1000.0) ** 2.5


def run(physics, seconds, each=None):
    for _ in range(int(round(seconds / STEP_S))):
        physics.step()
        if each:
            each(physics)


def open_valve(physics, command=2):
    physics.valve.command(command, physics.time)


def steady_config(**changes):
    """A rigid scale under a wide container and a flat heap (the fall height holds), no fluctuation."""
    config = PlantConfig(rigid=True, container_mm=4000.0, fluctuation=0.0, startup_s=0.05, noise_d=0.0,
                         dead_ms=0.0, stroke_ms=0.0, impact_relax_ms=0.0, silo_kg=500.0, repose_deg=1.0)
    for key, value in changes.items():
        setattr(config, key, value)
    return config


class Conservation(unittest.TestCase):
    def test_released_is_landed_plus_in_flight_at_every_step(self):
        config = PlantConfig(noise_d=0.0, fluctuation=0.05, silo_kg=12.0)
        physics = Physics(config)
        worst = [0.0]

        def check(p):
            worst[0] = max(worst[0], abs(config.silo_kg - p.silo_kg - p.released_kg),
                           abs(p.released_kg - p.landed_kg - p.in_flight_kg))
            self.assertGreaterEqual(p.in_flight_kg, -1e-12)

        open_valve(physics)
        run(physics, 2.0, check)
        physics.valve.command(1, physics.time)
        run(physics, 1.0, check)
        physics.valve.command(0, physics.time)
        run(physics, 8.0, check)
        self.assertLess(worst[0], 1e-9)
        self.assertGreater(physics.released_kg, 2.0)
        self.assertEqual(physics.in_flight_kg, 0.0)
        # at rest the load cell reads g times the released mass
        counts, status = physics.sample()
        self.assertEqual(status, 0)
        self.assertAlmostEqual((counts - config.offset_counts) / config.counts_per_kg, physics.released_kg,
                               delta=2.0 / config.counts_per_kg + 1e-5)

    def test_an_empty_silo_stops_the_flow(self):
        physics = Physics(PlantConfig(silo_kg=0.5, noise_d=0.0))
        open_valve(physics)
        run(physics, 4.0)
        self.assertEqual(physics.silo_kg, 0.0)
        self.assertAlmostEqual(physics.landed_kg, 0.5, places=9)
        self.assertEqual(physics.flow_kg_s, 0.0)


class SteadyStream(unittest.TestCase):
    def test_flow_in_flight_and_impact_force(self):
        config = steady_config()
        physics = Physics(config)
        open_valve(physics)
        run(physics, 1.5)  # start-up (0.05 s) and the first fall are long over
        w = beverloo(config)
        v0 = w / (config.density * math.pi * (config.bore_mm / 1000.0) ** 2 / 4.0)
        samples = []

        def record(p):
            samples.append((p.flow_kg_s, p.in_flight_kg, p.cell_force_n() / G - p.landed_kg,
                            p.fall_height_m()))

        run(physics, 0.5, record)
        flow = sum(s[0] for s in samples) / len(samples)
        in_flight = sum(s[1] for s in samples) / len(samples)
        excess_kg = sum(s[2] for s in samples) / len(samples)  # reading above what has landed
        h = sum(s[3] for s in samples) / len(samples)
        v = math.sqrt(v0 * v0 + 2.0 * G * h)
        fall_s = (v - v0) / G
        self.assertAlmostEqual(flow, w, delta=0.001 * w)
        self.assertAlmostEqual(in_flight, w * fall_s, delta=0.01 * w * fall_s)
        # F_imp = mdot v: the reading exceeds the landed mass by mdot v / g
        self.assertAlmostEqual(excess_kg, w * v / G, delta=0.02 * w * v / G)
        # ... which is the material in flight plus mdot v0 / g (the corrected sign: plus)
        self.assertAlmostEqual(excess_kg - in_flight, w * v0 / G, delta=0.05 * w * v0 / G)

    def test_default_scene_numbers_of_the_reference(self):
        """Rho 1550, D 60 mm, d 0.5 mm: W about 2.41 kg/s, v0 about 0.55 m/s, 1.06 kg in flight
        over 1.2 m, mdot v0 / g about 135 g."""
        config = steady_config(density=1550.0, bore_mm=60.0, fall_mm=1200.0)
        physics = Physics(config)
        self.assertAlmostEqual(physics.full_flow_kg_s(), 2.41, delta=0.02)
        self.assertAlmostEqual(physics.outflow_speed(), 0.55, delta=0.01)
        open_valve(physics)
        run(physics, 1.0)
        self.assertAlmostEqual(physics.in_flight_kg, 1.06, delta=0.02)

    def test_at_an_instant_close_the_reading_exceeds_the_final_weight_by_mdot_v0_over_g(self):
        config = steady_config()
        physics = Physics(config)
        open_valve(physics)
        run(physics, 1.5)
        flow = physics.flow_kg_s
        v0 = flow / (config.density * physics.bore_area)
        physics.valve.command(0, physics.time)
        reading_at_close = physics.cell_force_n() / G
        run(physics, 2.0)
        final = physics.cell_force_n() / G
        self.assertAlmostEqual(final, physics.released_kg, places=9)
        excess = reading_at_close - final
        self.assertGreater(excess, 0.0)
        self.assertAlmostEqual(excess, flow * v0 / G, delta=0.05 * flow * v0 / G)

    def test_first_grains_land_after_the_dead_time_and_the_fall(self):
        config = steady_config(dead_ms=40.0, startup_s=0.15)
        physics = Physics(config)
        open_valve(physics)
        landed_at = []
        run(physics, 1.5, lambda p: landed_at.append(p.time) if p.landed_kg > 0 and not landed_at else None)
        # the first grains leave at rest (the flow starts up from zero): t = sqrt(2 h / g)
        expected = config.dead_ms / 1000.0 + math.sqrt(2.0 * config.fall_mm / 1000.0 / G)
        self.assertAlmostEqual(landed_at[0], expected, delta=0.003)


class Platform(unittest.TestCase):
    def ringing(self, load_kg):
        config = PlantConfig(noise_d=0.0, platform_kg=5.0, platform_hz=10.0, damping=0.02)
        physics = Physics(config)
        physics.set_test_weight(load_kg, 0.0)
        trace = []
        run(physics, 3.0, lambda p: trace.append(p.cell_force_n() / G - load_kg))
        crossings = [i for i in range(1, len(trace)) if trace[i - 1] < 0.0 <= trace[i]]
        period_s = (crossings[-1] - crossings[0]) * STEP_S / (len(crossings) - 1)
        peaks = [max(trace[a:b]) for a, b in zip(crossings, crossings[1:])]
        cycles = len(peaks) - 1
        zeta = math.log(peaks[0] / peaks[-1]) / (2.0 * math.pi * cycles)
        return 1.0 / period_s, zeta, config

    def test_frequency_and_damping_follow_the_moving_mass(self):
        for load in (1.0, 10.0, 30.0):
            with self.subTest(load_kg=load):
                hz, zeta, config = self.ringing(load)
                moving = config.platform_kg + load
                self.assertAlmostEqual(hz, config.platform_hz * math.sqrt(config.platform_kg / moving),
                                       delta=0.005 * hz)
                self.assertAlmostEqual(zeta, config.damping * math.sqrt(config.platform_kg / moving),
                                       delta=0.1 * zeta)

    def test_a_gentle_set_down_rings_less(self):
        def amplitude(ramp_s):
            physics = Physics(PlantConfig(noise_d=0.0, platform_kg=25.0, platform_hz=5.0, damping=0.02))
            physics.set_test_weight(10.0, ramp_s)
            run(physics, ramp_s + 0.5)
            trace = []
            run(physics, 1.0, lambda p: trace.append(abs(p.cell_force_n() / G - 10.0)))
            return max(trace)

        self.assertGreater(amplitude(0.0), 5.0)  # a dropped weight rings with about its own size
        self.assertLess(amplitude(0.5), 0.15 * amplitude(0.0))


class ValveAndLoadCell(unittest.TestCase):
    def test_dead_time_stroke_and_feedback(self):
        for reports_moving in (True, False):
            config = PlantConfig(dead_ms=70.0, stroke_ms=250.0, reports_moving=reports_moving)
            physics = Physics(config)
            physics.valve.command(2, 0.0035)
            seen = {}
            run(physics, 0.6, lambda p: seen.setdefault(round(p.time * 1000), (p.valve.position, p.valve.feedback())))
            self.assertEqual(seen[73][0], 0.0)
            self.assertGreater(seen[75][0], 0.0)
            self.assertLess(seen[323][0], 1.0)
            self.assertEqual(seen[324][0], 1.0)
            self.assertEqual(seen[200][1], 1 if reports_moving else 0)
            self.assertEqual(seen[400][1], 3)
            physics.valve.command(0, physics.time)
            closing = []
            run(physics, 0.5, lambda p: closing.append(p.valve.feedback()))
            self.assertEqual(closing[150], 1 if reports_moving else 3)  # latched limit switch: still open
            self.assertEqual(closing[-1], 0)

    def test_a_stuck_valve_does_not_close(self):
        physics = Physics(PlantConfig())
        open_valve(physics)
        run(physics, 0.5)
        physics.valve.stuck = True
        physics.valve.command(0, physics.time)
        run(physics, 0.5)
        self.assertEqual(physics.valve.position, 1.0)
        self.assertEqual(physics.valve.feedback(), 3)
        self.assertGreater(physics.flow_kg_s, 0.5 * physics.full_flow_kg_s())

    def test_half_open_is_half_the_bore_drawn(self):
        self.assertAlmostEqual(open_area_fraction(0.5), 0.5, places=12)
        self.assertEqual(open_area_fraction(0.0), 0.0)
        self.assertEqual(open_area_fraction(1.0), 1.0)

    def test_offset_gain_and_the_int32_range(self):
        for offset, gain in ((-2_000_000_000, 100_000.0), (0, 1.0), (2_000_000_000, 20_000.0)):
            physics = Physics(PlantConfig(rigid=True, noise_d=0.0, offset_counts=offset, counts_per_kg=gain))
            run(physics, 0.01)
            self.assertEqual(physics.sample(), (offset, 0))
            physics.set_test_weight(10.0, 0.0)
            run(physics, 0.01)
            self.assertEqual(physics.sample(), (offset + round(10.0 * gain), 0))
        physics = Physics(PlantConfig(rigid=True, noise_d=0.0, offset_counts=INT32_MAX - 100, counts_per_kg=1000.0))
        physics.set_test_weight(1.0, 0.0)
        run(physics, 0.01)
        self.assertEqual(physics.sample(), (INT32_MAX, STATUS_OVERLOAD))

    def test_noise_is_stated_in_scale_divisions(self):
        physics = Physics(PlantConfig(rigid=True, noise_d=3.0, counts_per_kg=100_000.0, offset_counts=0))
        readings = [physics.sample()[0] / 100.0 for _ in range(4000)]  # 100 counts per g
        mean = sum(readings) / len(readings)
        rms = math.sqrt(sum((r - mean) ** 2 for r in readings) / len(readings))
        self.assertAlmostEqual(rms, 3.0, delta=0.15)


if __name__ == "__main__":
    unittest.main(verbosity=2)
