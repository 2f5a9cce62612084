#!/usr/bin/env python3
"""Supervision that knows the valve it has. Valves from 10 to 80 ms dead time and
40 to 300 ms stroke, with feedback that reports `moving` (position 1) through the stroke and
feedback that does not (two latching limit switches: open until the closed switch makes), the
valve parameters left at their defaults (only bore, fall, container and density set):

- three healthy `dose 3000`, each sent right after the previous answer: every one ends in RESULT
  and OK, and the indicator's status (0x181) never shows a fault (no `valve_stuck_open`);
- the third fill within 90 g of its target (the cutoff uses the timing it has seen);
- then the valve sticks open: `dose 3000` answers `ERR 4 fault valve_stuck_open`, and the 0x181
  shows the fault no later than 100 ms (plus the 10 ms jiffy it is seen in) after the moment a
  healthy valve of this timing would have shut (the close command, its delay, dead time, stroke).
Each fill's truth error is printed."""
import argparse

from outside_plant import JIFFY_S, OutsidePlant
from outside_plant_checks import (DoseLog, Failures, factory_like_config, installation_params, protocol_clean,
                                  run_protected)

VALVES = [  # dead ms, stroke ms, feedback reports moving, then sticks open
    (10.0, 40.0, True, False),
    (40.0, 150.0, False, False),
    (70.0, 250.0, True, False),
    (70.0, 250.0, False, True),
    (80.0, 300.0, True, True),
]
HEALTHY_DOSES = 3
TARGET_G = 3000
CATCH_WITHIN_S = 0.100
# The last healthy fill, once the indicator has seen the valve twice, within the in-service
# deviation of class X(2) for 3 kg (2 x 1.5 % = 90 g): twice what a datasheet-speed valve
# (10 ms / 40 ms) reaches on this plant (-21 to -43 g), where the cutoff's timing from the
# datasheet's 30 ms / 80 ms overdoses a 70 ms / 250 ms valve by 170-330 g.
LAST_FILL_WITHIN_G = 90.0


def close_after_last_open(plant, since_jiffy):
    """The 0x220 that closed the valve after the dose's last open command: (jiffy, delay)."""
    opened = False
    close = None
    for record in plant.commands:
        if record.jiffy < since_jiffy:
            continue
        if record.command != 0:
            opened, close = True, None
        elif opened and close is None:
            close = record
    return close


def first_fault_counter(plant, since_jiffy):
    faults = [c for c, (_, state, _) in plant.status_frames.items() if state == 3 and c >= since_jiffy]
    return min(faults) if faults else None


def one_valve(fw, failures, dead_ms, stroke_ms, moving, sticks):
    name = f"valve dead={dead_ms:g}ms stroke={stroke_ms:g}ms feedback={'moving' if moving else 'limit switches'}"
    print(f"=== {name}")
    holder = {}

    def body():
        config = factory_like_config(dead_ms=dead_ms, stroke_ms=stroke_ms, reports_moving=moving, seed=int(dead_ms))
        plant = holder["plant"] = OutsidePlant(fw, config)
        for line in installation_params(config):
            answer = plant.command(line, 10.0)
            failures.check(answer is not None and answer.ok, f"{name}: `{line}` answered {answer and answer.lines}")
        doses = DoseLog(plant)
        for _ in range(HEALTHY_DOSES):
            dose = doses.dose(TARGET_G)
            if not failures.check(dose.answer is not None and dose.answer.ok and dose.answer.line_starting("RESULT "),
                                  f"{name}: healthy dose {len(doses.doses)} answered "
                                  f"[{' | '.join(dose.answer.lines) if dose.answer else 'nothing in 90 s'}], "
                                  "not RESULT and OK"):
                break
        healthy_end = plant.jiffy
        false_faults = sorted(c for c, (_, s, _) in plant.status_frames.items() if s == 3 and c < healthy_end)
        failures.check(not false_faults, f"{name}: the indicator's status showed a fault during healthy doses "
                                         f"(first at t={false_faults[0] * JIFFY_S:.2f} s)" if false_faults else "")
        doses.finish(settle_seconds=2.0)
        doses.report()
        last = doses.doses[-1]
        if len(doses.doses) == HEALTHY_DOSES and last.answer and last.answer.ok:
            failures.check(abs(last.truth_g - TARGET_G) <= LAST_FILL_WITHIN_G,
                           f"{name}: fill {HEALTHY_DOSES} is {last.truth_g - TARGET_G:+.1f} g from its target, not within "
                           f"{LAST_FILL_WITHIN_G:.0f} g: the cutoff does not use the valve timing it has seen")
        healthy_ok = len(doses.doses) == HEALTHY_DOSES and all(d.answer and d.answer.ok for d in doses.doses)
        if sticks and not healthy_ok:
            print("the stuck-valve check is skipped: the healthy doses did not all succeed")
        if sticks and healthy_ok:
            plant.physics.valve.stuck = True
            print("operator: (the valve will stick open)")
            start = plant.jiffy
            answer = plant.command(f"dose {TARGET_G}", 60.0)
            failures.check(answer is not None and answer.final.startswith("ERR 4 fault valve_stuck_open"),
                           f"{name}: with the valve stuck open `dose {TARGET_G}` answered "
                           f"[{' | '.join(answer.lines) if answer else 'nothing in 60 s'}], "
                           "not `ERR 4 fault valve_stuck_open`")
            plant.run(0.1)  # the status frames of the answer's jiffy come with the next samples
            close = close_after_last_open(plant, start)
            fault = first_fault_counter(plant, start)
            if failures.check(close is not None and fault is not None,
                              f"{name}: no close command ({close}) or no fault status ({fault}) after it"):
                shut_s = close.jiffy * JIFFY_S + close.delay_100us * 1e-4 + (dead_ms + stroke_ms) / 1000.0
                late_s = fault * JIFFY_S - shut_s
                print(f"stuck valve: close command at {close.jiffy * JIFFY_S:.3f} s + {close.delay_100us / 10:.1f} ms, "
                      f"a healthy valve shut at {shut_s:.3f} s, fault shown at {fault * JIFFY_S:.3f} s "
                      f"({late_s * 1000:+.0f} ms)")
                failures.check(late_s <= CATCH_WITHIN_S + JIFFY_S + 1e-9,
                               f"{name}: the stuck valve was caught {late_s * 1000:.0f} ms after a healthy valve would "
                               f"have shut, not within {CATCH_WITHIN_S * 1000:.0f} ms")
        protocol_clean(plant, failures, f"{name}: ")

    run_protected(body, failures, holder, name)


def main():
    a = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    a.add_argument("--fw", required=True)
    args = a.parse_args()
    failures = Failures()
    for dead_ms, stroke_ms, moving, sticks in VALVES:
        one_valve(args.fw, failures, dead_ms, stroke_ms, moving, sticks)
    failures.done()


if __name__ == "__main__":
    main()
