#!/usr/bin/env python3
"""Commissioning a new scale over udp, each case on a fresh indicator (a new
--nvm file in a temporary directory):

1. A fresh indicator has no calibration: `dose 1000` answers `ERR 5 not calibrated`.
2. For load cells across the int32 range of offsets and gains of 1 to 100,000 counts/kg, with
   0.1 to 3 d of noise, on a soft platform that rings (5 Hz, damping 0.02, 25 kg moving): `zero`
   on the empty scale; a 10 kg test weight set down over 0.5 s and `cal 10000` sent 2 s later,
   while the platform still rings by about 1 % of the weight (an operator told `ERR 3 ... motion`
   may send `cal` again, at most three times); the weight taken off. Then `status` must read the
   empty scale as 0 and a 7.5 kg check load as 7500 g, each within BOUND (below).
3. A platform kept moving (+-50 g at 1.5 Hz, someone leaning on it) answers `zero` and `cal` with
   `ERR 3 ... motion` once the indicator's standstill timeout has run; still again, both are OK.

BOUND: 2 d (the display's rounding, 0.5 d, plus what is left of up to 3 d rms of noise after
the display filter and the mean of ten readings, about 0.3 d, plus the zero and span windows'
own noise) plus two counts of the ADC in grams (a gain of 1 count/kg cannot show a weight finer
than its 1000 g count: zero, span and reading each round by up to half a count)."""
import argparse
import os

from outside_plant import G, OutsidePlant, PlantConfig
from outside_plant_checks import Failures, fresh_nvm, run_protected, temp_dir

LOAD_CELLS = [  # (offset counts of the empty scale, counts per kg, noise in d)
    (-2_000_000_000, 100_000.0, 0.3),
    (-5_000_000, 20_000.0, 3.0),
    (0, 50.0, 1.0),
    (123_456, 1.0, 0.1),
    (2_000_000_000, 20_000.0, 0.5),
]
TEST_KG = 10.0
CHECK_KG = 7.5
SET_DOWN_S = 0.5
CAL_AFTER_S = 2.0
CAL_TRIES = 3
MOTION_MAX_S = 120.0  # longest the indicator may take to say `in motion`, plant time


def soft_platform(offset, gain, noise, seed):
    return PlantConfig(offset_counts=offset, counts_per_kg=gain, noise_d=noise, platform_kg=25.0,
                       platform_hz=5.0, damping=0.02, seed=seed)


def bound_g(gain):
    return 2.0 + 2.0 * 1000.0 / gain


def ringing_g(plant):
    """How far the platform is from rest now (the plant knows; the operator waits for it)."""
    p = plant.physics
    return abs(p.cell_force_n() / G - p.on_scale_kg()) * 1000.0


def settle(plant, limit_g=0.05, max_s=40.0):
    """The operator waits until the platform has stopped (as a display would show)."""
    plant.run_until(lambda: ringing_g(plant) < limit_g and abs(plant.physics.vy) < 1e-3, max_s)
    plant.run(1.0)


def mean_status_weight(plant, readings=10, spacing_s=0.2):
    weights = []
    for _ in range(readings):
        answer = plant.command("status", 10.0)
        line = answer.line_starting("STATUS ") if answer else None
        if not line:
            return None, answer.lines if answer else "no answer"
        weights.append(float(line.split("weight=")[1].split()[0]))
        plant.run(spacing_s)
    return sum(weights) / len(weights), weights


def answer_text(answer):
    return " | ".join(answer.lines) if answer else "no answer"


def is_motion_refusal(answer):
    return answer is not None and answer.final.startswith("ERR 3") and "motion" in answer.final


def uncalibrated_dose_refused(fw, failures, directory):
    holder = {}

    def body():
        plant = holder["plant"] = OutsidePlant(fw, soft_platform(-5_000_000, 20_000.0, 0.5, 7),
                                               nvm=fresh_nvm(directory + "/uncalibrated"))
        answer = plant.command("dose 1000", 90.0)  # typed before the first sample
        failures.check(answer is not None and answer.final == "ERR 5 not calibrated",
                       f"a fresh indicator (new --nvm file) answered `dose 1000` with [{answer_text(answer)}], "
                       "not `ERR 5 not calibrated`")
        failures.check(plant.physics.released_kg == 0.0,
                       f"the uncalibrated indicator opened the valve: {plant.physics.released_kg:.3f} kg released")

    os.makedirs(directory + "/uncalibrated")
    run_protected(body, failures, holder, "fresh indicator")


def commission(fw, failures, directory, offset, gain, noise, seed):
    name = f"offset={offset} gain={gain:g}/kg noise={noise}d"
    holder = {}

    def body():
        os.makedirs(directory)
        plant = holder["plant"] = OutsidePlant(fw, soft_platform(offset, gain, noise, seed),
                                               nvm=fresh_nvm(directory))
        plant.run(1.0)
        zero = plant.command("zero", 60.0)
        if not failures.check(zero is not None and zero.ok,
                              f"{name}: `zero` on the empty scale answered [{answer_text(zero)}], not OK"):
            return
        plant.put_weight(TEST_KG, SET_DOWN_S)
        plant.run(CAL_AFTER_S)
        print(f"platform off rest by {ringing_g(plant):.0f} g when `cal` is sent")
        for attempt in range(CAL_TRIES):
            cal = plant.command(f"cal {TEST_KG * 1000:.0f}", 60.0)
            if not is_motion_refusal(cal):
                break
            print(f"note: cal attempt {attempt + 1} refused in motion after "
                  f"{(cal.answered_jiffy - cal.sent_jiffy) * 0.01:.1f} s; the operator tries again")
        if not failures.check(cal is not None and cal.ok,
                              f"{name}: `cal 10000` answered [{answer_text(cal)}], not OK"):
            return
        print(f"cal answered after {(cal.answered_jiffy - cal.sent_jiffy) * 0.01:.2f} s")
        plant.take_weight(SET_DOWN_S)
        plant.run(SET_DOWN_S)  # the ramp first: before it moves, the platform is at rest
        settle(plant)
        empty, readings = mean_status_weight(plant)
        if not failures.check(empty is not None, f"{name}: status answered {readings}"):
            return
        plant.put_weight(CHECK_KG, 1.0)
        plant.run(1.0)
        settle(plant)
        loaded, readings = mean_status_weight(plant)
        if not failures.check(loaded is not None, f"{name}: status answered {readings}"):
            return
        bound = bound_g(gain)
        truth = CHECK_KG * 1000.0
        print(f"case {name}: empty_g={empty:.2f} check_g={loaded:.2f} truth_g={truth:.0f} "
              f"error_g={loaded - truth:.2f} bound_g={bound:.2f}")
        failures.check(abs(empty) <= bound, f"{name}: the empty scale reads {empty:.2f} g, not 0 within {bound:.2f} g")
        failures.check(abs(loaded - truth) <= bound,
                       f"{name}: a {CHECK_KG} kg load reads {loaded:.2f} g, not {truth:.0f} within {bound:.2f} g")

    run_protected(body, failures, holder, name)


def motion_refused(fw, failures, directory):
    holder = {}

    def body():
        os.makedirs(directory)
        plant = holder["plant"] = OutsidePlant(fw, soft_platform(0, 20_000.0, 0.5, 11), nvm=fresh_nvm(directory))
        plant.shake(0.05, 1.5)
        plant.run(1.0)
        for command, then in (("zero", lambda: plant.put_weight(TEST_KG, SET_DOWN_S)), ("cal 10000", None)):
            answer = plant.command(command, MOTION_MAX_S)
            waited = (answer.answered_jiffy - answer.sent_jiffy) * 0.01 if answer else None
            print(f"`{command}` on a moving platform: [{answer_text(answer)}] after {waited} s")
            failures.check(is_motion_refusal(answer),
                           f"`{command}` on a platform kept moving answered [{answer_text(answer)}] "
                           f"within {MOTION_MAX_S} s, not `ERR 3 ... motion`")
            failures.check(not is_motion_refusal(answer) or waited >= 0.5,
                           f"`{command}` was refused after {waited} s: no standstill window was waited for")
            plant.shake(0.0, 0.0)
            settle(plant)
            again = plant.command(command, 60.0)
            failures.check(again is not None and again.ok,
                           f"`{command}` once the platform is still answered [{answer_text(again)}], not OK")
            if then:
                then()
                settle(plant)
                plant.shake(0.05, 1.5)
                plant.run(1.0)

    run_protected(body, failures, holder, "moving platform")


def main():
    a = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    a.add_argument("--fw", required=True)
    a.add_argument("--only", choices=("uncalibrated", "commission", "motion"))
    args = a.parse_args()
    failures = Failures()
    with temp_dir() as directory:
        if args.only in (None, "uncalibrated"):
            uncalibrated_dose_refused(args.fw, failures, directory)
        if args.only in (None, "commission"):
            for i, (offset, gain, noise) in enumerate(LOAD_CELLS):
                commission(args.fw, failures, f"{directory}/cell{i}", offset, gain, noise, seed=100 + i)
        if args.only in (None, "motion"):
            motion_refused(args.fw, failures, f"{directory}/motion")
    failures.done()


if __name__ == "__main__":
    main()
