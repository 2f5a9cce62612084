#!/usr/bin/env python3
"""First contact end to end: the outside plant over udp, driven through --console stdio, commissions a
fresh indicator (new --nvm file) with `zero`, a 10 kg test weight and `cal 10000` at an arbitrary
offset and gain (-1,234,567,890 counts, 37,000 counts/kg, 0.7 d noise), tells it the installation
(bore, fall, container as built, the density 3 % off, a 100 kg scale), then doses 1000, 3000 and
6000 g five times each, back to back: each `dose` sent right after the previous answer. Required:
no protocol error (every sample answered once with its counter, the heartbeat kept), no fault
(no ERR, no fault state in the 0x181 status), no refused dose (no `ERR 3 busy`), each dose's
valve open as soon as the platform can have come to rest (rest_wait_bound_s: no waiting behind a
recording), and the
certified finals agreeing with the plant's truth. Each fill's truth error is printed."""
import argparse
import math
import os

from outside_plant import G, JIFFY_S, OutsidePlant, PlantConfig
from outside_plant_checks import (DoseLog, Failures, fresh_nvm, installation_params, protocol_clean, run_protected,
                                  temp_dir)

TARGETS = (1000, 3000, 6000)
REPEATS = 5
TEST_KG = 10.0
CAL_TRIES = 3
# The scale must be at rest before the valve opens (the stable window, 0.5 s by default, and what
# is left of the last fill's ringing on this 11 Hz platform); a dose held back behind the last
# one's 10 s test-data recording waits 5-8 s. The result is certified through the ringing, before
# the platform is at rest, so the next opening waits for rest, and the ring dies out the slower the
# more the hopper holds: its amplitude falls by e in 2 m / c (m the platform's and the load's mass, c
# the damper's constant), 0.3 s on the empty 8 kg platform, 1.9 s with 44 kg in the hopper. Measured
# here: 0.8-1.4 s after the 1 kg doses, up to 10 s with 44 kg on the scale. How large the ring is
# when the result comes depends on how the fill ended (20 to 370 g here, the most after a fill
# its close ended, the stream cut at full flow), so the bound allows the stable window and as many
# decay constants as the ring the plant shows at the last answer takes to fall into the 0.5 g the
# display must hold (at least REST_DECAY_CONSTANTS: a 75 g ring). A hold behind a recording after
# the short 1 kg doses (bounds of 2.0-2.7 s) still shows.
STABLE_WINDOW_S = 0.5
REST_DECAY_CONSTANTS = 5.0
REST_G = 0.5
AGREEMENT_G = 3.0  # certified final against the truth: the calibration's few d, nothing more


def rest_wait_bound_s(plant, load_kg, ring_g):
    """The longest a dose may wait for rest with `load_kg` on the scale and the platform ringing by
    `ring_g` when it was sent (None: no fill before it; see REST_DECAY_CONSTANTS)."""
    decay_s = 2.0 * (plant.config.platform_kg + load_kg) / plant.physics.damper
    constants = max(REST_DECAY_CONSTANTS, math.log(ring_g / REST_G)) if ring_g else REST_DECAY_CONSTANTS
    # The valve opens on the jiffy grid: the jiffy in which rest is seen, not the instant.
    return STABLE_WINDOW_S + constants * decay_s + JIFFY_S


def installation():
    return PlantConfig(offset_counts=-1_234_567_890, counts_per_kg=37_000.0, noise_d=0.7, bore_mm=50.0,
                       density=1450.0, fall_mm=1100.0, container_mm=450.0, platform_kg=8.0, platform_hz=11.0,
                       damping=0.05, dead_ms=45.0, stroke_ms=120.0, reports_moving=True, silo_kg=70.0,
                       capacity_kg=100.0, seed=14)


def main():
    a = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    a.add_argument("--fw", required=True)
    a.add_argument("--offset-counts", type=int, help="another load cell offset (by hand)")
    a.add_argument("--counts-per-kg", type=float, help="another load cell gain (by hand)")
    args = a.parse_args()
    failures = Failures()
    holder = {}
    config = installation()
    if args.offset_counts is not None:
        config.offset_counts = args.offset_counts
    if args.counts_per_kg is not None:
        config.counts_per_kg = args.counts_per_kg

    def commission(plant):
        plant.run(1.0)
        lines = installation_params(config, density=round(config.density * 1.03)) + ["param capacity_g 100000"]
        for line in lines:
            answer = plant.command(line, 10.0)
            failures.check(answer is not None and answer.ok, f"`{line}` answered {answer and answer.lines}")
        zero = plant.command("zero", 60.0)
        if not failures.check(zero is not None and zero.ok, f"`zero` answered {zero and zero.lines}, not OK"):
            return False
        plant.put_weight(TEST_KG, 0.5)
        plant.run(2.0)
        for _ in range(CAL_TRIES):
            cal = plant.command(f"cal {TEST_KG * 1000:.0f}", 60.0)
            if not (cal and cal.final.startswith("ERR 3") and "motion" in cal.final):
                break
        if not failures.check(cal is not None and cal.ok, f"`cal 10000` answered {cal and cal.lines}, not OK"):
            return False
        plant.take_weight(0.5)
        plant.run(2.0)
        return True

    def body():
        with temp_dir() as directory:
            plant = holder["plant"] = OutsidePlant(args.fw, config, nvm=fresh_nvm(directory))
            if not commission(plant):
                return
            doses = DoseLog(plant)
            for target in TARGETS:
                for _ in range(REPEATS):
                    dose = doses.dose(target)
                    if not failures.check(dose.answer is not None and dose.answer.ok
                                          and dose.answer.line_starting("RESULT "),
                                          f"dose {len(doses.doses)} ({target} g) answered "
                                          f"[{' | '.join(dose.answer.lines) if dose.answer else 'nothing in 90 s'}]"
                                          + (" (refused: busy)" if dose.answer and "ERR 3" in dose.answer.final
                                             else "")):
                        break
                else:
                    continue
                break
            doses.finish()
            plant.close_input()
            rc = plant.finish(max_seconds=30.0)
            doses.report()
            for i, d in enumerate(doses.doses, 1):
                if d.opened_jiffy is not None:
                    wait = (d.opened_jiffy - d.sent_jiffy) * JIFFY_S
                    ring_g = doses.doses[i - 2].ring_after_g if i > 1 else None
                    bound = rest_wait_bound_s(plant, d.released_before, ring_g)
                    print(f"dose {i} target={d.target} opened_after_s={wait:.2f} bound_s={bound:.2f} "
                          f"ring_before_g={ring_g or 0.0:.0f}")
                    failures.check(wait <= bound,
                                   f"dose {i} ({d.target} g) opened the valve {wait:.2f} s after `dose`, "
                                   f"not within {bound:.2f} s ({d.released_before:.1f} kg on the scale)")
                if d.reported_g is not None:
                    failures.check(abs(d.reported_g - d.truth_g) <= AGREEMENT_G,
                                   f"dose {i}: certified final {d.reported_g:.0f} g, truth {d.truth_g:.1f} g")
            faults = sorted(c for c, (_, s, _) in plant.status_frames.items() if s == 3)
            failures.check(not faults, f"the status (0x181) showed a fault at t={faults[0] * JIFFY_S:.2f} s"
                           if faults else "")
            failures.check(len(doses.doses) == len(TARGETS) * REPEATS,
                           f"{len(doses.doses)} of {len(TARGETS) * REPEATS} doses sent")
            failures.check(rc == 0, f"dynweigh-fw exited {rc} at the end of its input, not 0")
            protocol_clean(plant, failures)
            for target in TARGETS:
                errors = [d.truth_g - target for d in doses.doses if d.target == target and d.answer and d.answer.ok]
                if errors:
                    mean = sum(errors) / len(errors)
                    print(f"target={target} fills={len(errors)} mean_error_g={mean:.1f} "
                          f"worst_error_g={max(errors, key=abs):.1f}")
            for key, value in plant.summary().items():
                print(f"{key}={value}")
            print(f"container_kg={plant.physics.landed_kg:.3f} scale_capacity_kg={config.capacity_kg:g} "
                  f"reading_kg={plant.physics.cell_force_n() / G:.3f}")

    run_protected(body, failures, holder)
    failures.done()


if __name__ == "__main__":
    main()
