#!/usr/bin/env python3
"""The outside plant and its protocol against dynweigh-fw as it is: the load cell wired as the
default scene's (so the factory calibration weighs it right), every console line written before
the first sample, `dose 5000`, end of input. The dose completes, every sample is answered once
with its counter, and the certified final agrees with the plant's truth."""
import argparse

from outside_plant import OutsidePlant
from outside_plant_checks import DoseLog, Failures, factory_like_config, protocol_clean, run_protected

TRUTH_TOLERANCE_G = 100.0  # the in-process class of a 5 kg fill on the default scene (udp_dose.py)
AGREEMENT_G = 5.0          # certified final against the plant's truth

a = argparse.ArgumentParser(description=__doc__)
a.add_argument("--fw", required=True)
args = a.parse_args()
failures = Failures()
holder = {}


def scenario():
    plant = holder["plant"] = OutsidePlant(args.fw, factory_like_config())
    doses = DoseLog(plant)
    dose = doses.dose(5000)
    plant.close_input()
    doses.finish()
    rc = plant.finish()
    doses.report()
    failures.check(dose.answer is not None and dose.answer.ok and dose.answer.line_starting("RESULT "),
                   f"dose 5000 answered {dose.answer.lines if dose.answer else 'nothing'}, not RESULT and OK")
    failures.check(rc == 0, f"dynweigh-fw exited {rc} at end of input, not 0")
    protocol_clean(plant, failures)
    failures.check(abs(dose.truth_g - 5000) <= TRUTH_TOLERANCE_G,
                   f"true fill {dose.truth_g:.1f} g is more than {TRUTH_TOLERANCE_G} g from 5000 g")
    if dose.reported_g is not None:
        failures.check(abs(dose.reported_g - dose.truth_g) <= AGREEMENT_G,
                       f"certified final {dose.reported_g:.0f} g disagrees with the truth {dose.truth_g:.1f} g")
    for key, value in plant.summary().items():
        print(f"{key}={value}")


run_protected(scenario, failures, holder)
failures.done()
