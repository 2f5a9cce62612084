#!/usr/bin/env python3
"""The control loop never waits on the console: the outside plant sends samples
for 2 s before the first console line and requires the 0x220 answering each (its counter, once),
and the indicator's heartbeat every 100 ms; then the operator asks `status` and doses 3000 g, and
closes the input while the dose runs: the dose finishes (RESULT, OK) and dynweigh-fw exits 0."""
import argparse

from outside_plant import OutsidePlant
from outside_plant_checks import Dose, Failures, factory_like_config, protocol_clean, run_protected

IDLE_S = 2.0

a = argparse.ArgumentParser(description=__doc__)
a.add_argument("--fw", required=True)
args = a.parse_args()
failures = Failures()
holder = {}


def scenario():
    plant = holder["plant"] = OutsidePlant(args.fw, factory_like_config())
    plant.run(IDLE_S)  # a ProtocolError here: a sample unanswered while no line has come
    failures.check(plant.answers_received == plant.jiffy == round(IDLE_S / 0.01),
                   f"{plant.jiffy} samples in the idle {IDLE_S} s, {plant.answers_received} answered")
    failures.check(plant.heartbeat_gaps_ok(0, plant.jiffy - 1),
                   "no heartbeat 0x701 every 100 ms while idle with the console open")
    status = plant.command("status", 10.0)
    failures.check(status is not None and status.ok and status.line_starting("STATUS "),
                   f"status answered {status.lines if status else 'nothing'}")
    sent = plant.jiffy
    plant.send("dose 3000")
    plant.close_input()  # end of input with the dose in progress
    dose = Dose(3000, "model", sent, 0.0)
    dose.answer = plant.wait_answer("dose 3000", 90.0, sent)
    rc = plant.finish()
    dose.released_after = plant.physics.released_kg
    failures.check(dose.answer is not None and dose.answer.ok and dose.answer.line_starting("RESULT "),
                   "the dose in progress at end of input did not finish with RESULT and OK: "
                   f"{dose.answer.lines if dose.answer else 'no answer'}")
    failures.check(rc == 0, f"dynweigh-fw exited {rc} after the end of its input, not 0")
    protocol_clean(plant, failures)
    print(f"fill target=3000 truth_g={dose.truth_g:.1f} error_g={dose.truth_g - 3000:.1f}")
    for key, value in plant.summary().items():
        print(f"{key}={value}")


run_protected(scenario, failures, holder)
failures.done()
