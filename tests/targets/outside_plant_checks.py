"""What the outside-plant acceptance tests share: plant set-ups, the protocol's bookkeeping, doses
judged by the plant's truth, and one FAIL line per broken requirement."""
import math
import os
import sys
import tempfile

from outside_plant import G, JIFFY_S, OutsidePlant, PlantConfig, ProtocolError
from targets_common import field


class Failures:
    """Collects the requirements a run broke; `done()` prints them and exits 1, or PASS."""

    def __init__(self):
        self.items = []

    def check(self, condition, message):
        if not condition:
            self.items.append(message)
            print(f"FAIL: {message}", flush=True)
        return condition

    def done(self):
        if self.items:
            print(f"{len(self.items)} requirement(s) failed:")
            for item in self.items:
                print(f"  - {item}")
            sys.exit(1)
        print("PASS")
        sys.exit(0)


def factory_like_config(**changes):
    """A plant whose load cell reads as the default scene's does (empty scale, container on it,
    at 12,000 counts; 1,000 counts per kg), so an indicator with the factory calibration weighs
    it right: the tests of the lockstep and the valves need no commissioning. The rest of the plant
    is still this one's own physics."""
    config = PlantConfig(offset_counts=12_000, counts_per_kg=1000.0, noise_d=0.3, bore_mm=60.0,
                         density=1550.0, fall_mm=1200.0, container_mm=300.0, platform_kg=4.0,
                         platform_hz=12.0, damping=0.05, dead_ms=30.0, stroke_ms=80.0)
    for key, value in changes.items():
        setattr(config, key, value)
    return config


def installation_params(config, density=None):
    """The `param` lines an integrator types: the installation's bore, fall and container, and a
    rough bulk density."""
    return [f"param bore_mm {config.bore_mm:g}", f"param fall_mm {config.fall_mm:g}",
            f"param container_mm {config.container_mm:g}",
            f"param density {density if density is not None else config.density:g}"]


def fresh_nvm(directory):
    return os.path.join(directory, "dynweigh.nvm")


def protocol_clean(plant, failures, what=""):
    """Every sample answered exactly once with its counter; the indicator's heartbeat kept up."""
    failures.check(not plant.protocol_errors,
                   f"{what}protocol errors: " + "; ".join(plant.protocol_errors[:5]))
    failures.check(plant.answers_received == plant.jiffy,
                   f"{what}{plant.jiffy} samples sent, {plant.answers_received} answered")
    failures.check(plant.heartbeat_gaps_ok(0, plant.jiffy - 1),
                   f"{what}the indicator's heartbeat (0x701) missed its 100 ms somewhere in {plant.jiffy} jiffies")


class Dose:
    def __init__(self, target, strategy, sent_jiffy, released_before):
        self.target, self.strategy = target, strategy
        self.sent_jiffy = sent_jiffy
        self.released_before = released_before
        self.released_after = None
        self.answer = None
        self.opened_jiffy = None
        self.ring_after_g = None  # the platform's ring when the answer came (the plant's truth)

    @property
    def truth_g(self):
        return (self.released_after - self.released_before) * 1000.0

    @property
    def reported_g(self):
        line = self.answer.line_starting("RESULT ") if self.answer else None
        return float(field(line, "final")) if line else None


class DoseLog:
    """Doses sent one after the other; each fill's truth is what left the silo between its own
    `dose` and the next one (the valve opens only in a dose), so material in flight at the result
    still counts."""

    def __init__(self, plant):
        self.plant = plant
        self.doses = []

    def dose(self, target, strategy="", max_seconds=90.0):
        plant = self.plant
        self._close_previous()
        line = f"dose {target}" + (f" {strategy}" if strategy else "")
        dose = Dose(target, strategy or "model", plant.jiffy, plant.physics.released_kg)
        self.doses.append(dose)
        dose.answer = plant.command(line, max_seconds)
        dose.ring_after_g = plant.physics.ring_n() / G * 1000.0
        opens = plant.open_commands_since(dose.sent_jiffy)
        dose.opened_jiffy = opens[0].jiffy if opens else None
        return dose

    def _close_previous(self):
        if self.doses and self.doses[-1].released_after is None:
            self.doses[-1].released_after = self.plant.physics.released_kg

    def finish(self, settle_seconds=3.0):
        """The last fill's stream lands and rests before it is judged."""
        if self.doses and self.doses[-1].released_after is None:
            self.plant.run(settle_seconds)
            self._close_previous()

    def report(self):
        print(f"{'#':>3} {'target':>7} {'truth_g':>9} {'error_g':>8} {'reported':>9} {'rep-truth':>9} "
              f"{'wait_s':>6} answer")
        for i, d in enumerate(self.doses, 1):
            truth = d.truth_g if d.released_after is not None else float("nan")
            reported = d.reported_g
            wait = (d.opened_jiffy - d.sent_jiffy) * JIFFY_S if d.opened_jiffy is not None else float("nan")
            print(f"{i:>3} {d.target:>7} {truth:>9.1f} {truth - d.target:>8.1f} "
                  f"{reported if reported is not None else float('nan'):>9.0f} "
                  f"{(reported - truth) if reported is not None else float('nan'):>9.1f} {wait:>6.2f} "
                  f"{d.answer.final if d.answer else 'no answer'}")
        for d in self.doses:
            if d.released_after is not None:
                print(f"fill target={d.target} truth_g={d.truth_g:.1f} error_g={d.truth_g - d.target:.1f}")


def run_protected(body, failures, plant_holder, name=""):
    """Runs the scenario; a protocol error (a sample left unanswered) ends it as a failure."""
    try:
        body()
    except ProtocolError as e:
        failures.check(False, (f"{name}: " if name else "") + f"protocol error: {e}")
    finally:
        plant = plant_holder.get("plant")
        if plant:
            plant.close()
            if plant.stderr_text.strip():
                print("--- dynweigh-fw stderr ---\n" + plant.stderr_text.strip())


def temp_dir():
    return tempfile.TemporaryDirectory(prefix="outside_plant_")


def isfinite(x):
    return x is not None and not math.isnan(x)
