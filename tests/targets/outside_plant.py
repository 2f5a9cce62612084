#!/usr/bin/env python3
"""An outside plant: a silo, a valve, a falling stream, a ringing scale and a load cell that the
indicator has never met, written from the physics (not from sim/), speaking the indicator's CAN
protocol over the udp transport in lockstep, with an operator who types console lines and sets test
weights down. It keeps the truth (mass released, in flight, landed) to judge the indicator by.

Used by the outside_plant_*.py acceptance tests; run by hand with --help (docs/outside-plant.md).
Python 3 standard library only.
"""
import argparse
import collections
import math
import os
import random
import select
import socket
import struct
import subprocess
import sys
import time
from dataclasses import dataclass, field, fields

G = 9.81
STEP_S = 0.001          # physics step
JIFFY_S = 0.010         # one load-cell sample per jiffy
STEPS_PER_JIFFY = 10
PLATFORM_SUBSTEPS = 2   # the oscillator at 0.5 ms: < 0.05 % frequency error at 30 Hz

# CAN identifiers and node ids (CANopen conventions)
ID_SAMPLE = 0x190          # load cell -> indicator: int32 counts, uint16 counter, uint8 status, 0
ID_VALVE_COMMAND = 0x220   # indicator -> valve: uint8 command, uint8 delay (0.1 ms), uint16 counter
ID_VALVE_FEEDBACK = 0x1A0  # valve -> indicator: uint8 position (0 closed, 1 moving, 2 half, 3 open), faults
ID_STATUS = 0x181          # indicator -> anyone: int32 weight 0.1 g, state, valve, uint16 counter
ID_HEARTBEAT = 0x700
NODE_INDICATOR, NODE_LOAD_CELL, NODE_VALVE = 0x01, 0x10, 0x20
NMT_BOOT_UP, NMT_STOPPED, NMT_OPERATIONAL = 0x00, 0x04, 0x05
STATUS_OVERLOAD, STATUS_UNDERLOAD, STATUS_ADC_ERROR = 1, 2, 4
INDICATOR_STATES = {0: "idle", 1: "dosing", 2: "settling", 3: "fault"}
INT32_MIN, INT32_MAX = -(1 << 31), (1 << 31) - 1


def pack_frame(can_id, data):
    """One Linux struct can_frame: can_id u32 LE, len u8, 3 pad bytes, data[8]."""
    return struct.pack("<IB3x8s", can_id, len(data), bytes(data))


def unpack_frame(datagram):
    if len(datagram) != 16:
        return None
    can_id, length = struct.unpack_from("<IB", datagram)
    return can_id & 0x1FFFFFFF, datagram[8:8 + min(length, 8)]


@dataclass
class PlantConfig:
    """Every parameter of the plant. Defaults: a 50 mm silo outlet, 1.1 m fall, 9 Hz platform,
    a load cell with an arbitrary offset and gain, a valve a little slower than a datasheet's."""
    # silo and outlet (Beverloo: W = C rho sqrt(g) (D - k d)^2.5)
    density: float = 1450.0         # bulk density, kg/m^3
    bore_mm: float = 50.0           # outlet (valve bore) diameter
    grain_mm: float = 0.5
    beverloo_c: float = 0.58
    beverloo_k: float = 1.5
    silo_kg: float = 80.0           # material in the silo at start
    startup_s: float = 0.10         # the flow settles after opening with this time constant (0.05-0.5 s)
    fluctuation: float = 0.03       # rms of the relative flow fluctuation
    fluctuation_s: float = 0.15     # its correlation time
    # valve (a slide gate across the bore)
    dead_ms: float = 45.0           # command to first motion
    stroke_ms: float = 120.0        # full stroke, closed to open
    reports_moving: bool = True     # feedback 1 (moving) through the stroke; else two latching limit switches
    # fall and container
    fall_mm: float = 1100.0         # outlet to the empty container's bottom
    container_mm: float = 400.0     # container diameter
    repose_deg: float = 33.0        # angle of repose of the heap
    impact_relax_ms: float = 8.0    # landing momentum reaches the platform with this time constant
    # platform: a damped oscillator whose moving mass grows with the load
    platform_kg: float = 6.0        # moving mass of platform and empty container
    platform_hz: float = 9.0        # natural frequency with platform_kg
    damping: float = 0.04           # damping ratio with platform_kg
    rigid: bool = False             # no ringing: the load cell reads the force of the instant
    # load cell and ADC
    offset_counts: int = -5_000_000  # reading of the empty scale (container on it)
    counts_per_kg: float = 20000.0
    noise_d: float = 0.5            # rms noise in scale divisions
    d_g: float = 1.0                # one scale division, g
    capacity_kg: float = 100.0      # overload above 110 %
    seed: int = 1

    def describe(self):
        return " ".join(f"{f.name}={getattr(self, f.name)}" for f in fields(self))


class Valve:
    """Slide gate: a command takes effect at its time plus the dead time, then the gate moves at
    1/stroke per second towards 0 (closed), 0.5 (half) or 1 (open). A stuck valve ignores every
    command to close further than it is."""

    TARGETS = {0: 0.0, 1: 0.5, 2: 1.0}

    def __init__(self, dead_s, stroke_s, reports_moving):
        self.dead_s, self.stroke_s, self.reports_moving = dead_s, stroke_s, reports_moving
        self.position = 0.0
        self.target = 0.0
        self.time = 0.0
        self.pending = collections.deque()  # (time the motion starts, target)
        self.stuck = False
        self.last_command = 0
        self.limit = 0                      # the latching limit switches' last report (0 or 3)

    def command(self, command, at_time):
        if command == self.last_command:
            return
        self.last_command = command
        self.pending.append((at_time + self.dead_s, self.TARGETS[command]))

    def _move(self, until):
        span = until - self.time
        if span > 0.0 and self.position != self.target:
            step = span / self.stroke_s if self.stroke_s > 0.0 else 1.0
            if self.position < self.target:
                self.position = min(self.target, self.position + step)
            else:
                self.position = max(self.target, self.position - step)
        self.time = until

    def advance(self, until):
        while self.pending and self.pending[0][0] <= until:
            when, target = self.pending.popleft()
            self._move(max(when, self.time))
            if not (self.stuck and target < self.position):
                self.target = target
        self._move(until)
        if self.position <= 0.02:
            self.limit = 0
        elif self.position >= 0.98:
            self.limit = 3

    def feedback(self):
        """0 closed, 1 moving, 2 half, 3 open."""
        if self.position == self.target:
            if self.target == 0.0:
                return 0
            return 3 if self.target == 1.0 else 2
        return 1 if self.reports_moving else self.limit


def open_area_fraction(s):
    """A slide gate drawn a fraction s across a circular bore uncovers a circular segment."""
    if s <= 0.0:
        return 0.0
    if s >= 1.0:
        return 1.0
    theta = 2.0 * math.acos(1.0 - 2.0 * s)
    return (theta - math.sin(theta)) / (2.0 * math.pi)


class Physics:
    """The plant's state and its 1 ms step. All masses in kg, forces in N, times in s."""

    def __init__(self, config):
        c = self.config = config
        self.rng = random.Random(c.seed)
        self.time = 0.0
        self.valve = Valve(c.dead_ms / 1000.0, c.stroke_ms / 1000.0, c.reports_moving)
        bore = c.bore_mm / 1000.0
        self.bore_area = math.pi * bore * bore / 4.0
        # the truth
        self.silo_kg = c.silo_kg
        self.released_kg = 0.0
        self.landed_kg = 0.0
        self.in_flight_kg = 0.0
        self.parcels = collections.deque()  # [mass, release time, outflow speed]
        self.flow_kg_s = 0.0
        self.flowing_since = None
        self.fluct = 0.0
        self.impulse_n_s = 0.0              # landed momentum not yet passed to the platform
        self.impact_n = 0.0
        # the operator's loads: test weights set down or taken off along a raised-cosine ramp
        self.weight_from_kg = self.weight_to_kg = 0.0
        self.weight_ramp_start = 0.0
        self.weight_ramp_s = 0.0
        self.shake_kg, self.shake_hz = 0.0, 0.0
        # platform: deflection force k*y (N above the empty scale) and velocity
        self.stiffness = c.platform_kg * (2.0 * math.pi * c.platform_hz) ** 2
        self.damper = 2.0 * c.damping * math.sqrt(self.stiffness * c.platform_kg)
        self.y = 0.0
        self.vy = 0.0
        self.container_area = math.pi * (c.container_mm / 1000.0) ** 2 / 4.0

    # --- silo and outlet ------------------------------------------------------------------------
    def beverloo_kg_s(self, diameter_m):
        c = self.config
        free = diameter_m - c.beverloo_k * c.grain_mm / 1000.0
        return c.beverloo_c * c.density * math.sqrt(G) * free ** 2.5 if free > 0.0 else 0.0

    def full_flow_kg_s(self):
        return self.beverloo_kg_s(self.config.bore_mm / 1000.0)

    def outflow_speed(self):
        """v0 of the full stream: the mass flow through the bore at bulk density."""
        return self.full_flow_kg_s() / (self.config.density * self.bore_area)

    def _outlet_flow(self, opening):
        """Mass flow and outflow speed through an opening (area fraction) this step."""
        c = self.config
        if opening <= 0.0 or self.silo_kg <= 0.0:
            self.flowing_since = None
            return 0.0, 0.0
        if self.flowing_since is None:
            self.flowing_since = self.time
            self.fluct = 0.0
        diameter = c.bore_mm / 1000.0 * math.sqrt(opening)  # the circle of the same area
        steady = self.beverloo_kg_s(diameter)
        settle = 1.0 - math.exp(-(self.time - self.flowing_since) / c.startup_s) if c.startup_s > 0 else 1.0
        if c.fluctuation > 0.0:
            keep = math.exp(-STEP_S / c.fluctuation_s)
            self.fluct = self.fluct * keep + c.fluctuation * math.sqrt(1.0 - keep * keep) * self.rng.gauss(0.0, 1.0)
        flow = max(0.0, steady * settle * (1.0 + self.fluct))
        return flow, flow / (c.density * self.bore_area * opening)

    # --- pile -------------------------------------------------------------------------------------
    def pile_top_m(self):
        """Height of the heap's top above the container bottom: a cone at the angle of repose
        under the stream, then a cylinder with that cone on it once the cone spans the container."""
        c = self.config
        volume = self.landed_kg / c.density
        if volume <= 0.0:
            return 0.0
        slope = math.tan(math.radians(c.repose_deg))
        radius = c.container_mm / 2000.0
        full_cone = math.pi * radius ** 3 * slope / 3.0
        if volume <= full_cone:
            return (3.0 * volume / (math.pi * slope)) ** (1.0 / 3.0) * slope
        return (volume - full_cone) / self.container_area + radius * slope

    def fall_height_m(self):
        return max(0.0, self.config.fall_mm / 1000.0 - self.pile_top_m())

    # --- operator ---------------------------------------------------------------------------------
    def test_weight_kg(self, at=None):
        t = self.time if at is None else at
        if self.weight_ramp_s <= 0.0 or t >= self.weight_ramp_start + self.weight_ramp_s:
            return self.weight_to_kg
        if t <= self.weight_ramp_start:
            return self.weight_from_kg
        share = 0.5 - 0.5 * math.cos(math.pi * (t - self.weight_ramp_start) / self.weight_ramp_s)
        return self.weight_from_kg + (self.weight_to_kg - self.weight_from_kg) * share

    def set_test_weight(self, kg, ramp_s):
        self.weight_from_kg = self.test_weight_kg()
        self.weight_to_kg = kg
        self.weight_ramp_start = self.time
        self.weight_ramp_s = ramp_s

    # --- the step ---------------------------------------------------------------------------------
    def step(self):
        c = self.config
        t0, t1 = self.time, self.time + STEP_S
        self.valve.advance(t0 + STEP_S / 2)
        opening = open_area_fraction(self.valve.position)
        flow, v0 = self._outlet_flow(opening)
        self.valve.advance(t1)
        released = min(self.silo_kg, flow * STEP_S)
        if released > 0.0:
            self.silo_kg -= released
            self.released_kg += released
            self.in_flight_kg += released
            self.parcels.append([released, t0 + STEP_S / 2, v0])
        self.flow_kg_s = released / STEP_S
        # landing on the heap as it is now
        height = self.fall_height_m()
        momentum = 0.0
        while self.parcels:
            mass, released_at, speed = self.parcels[0]
            fall_s = (math.sqrt(speed * speed + 2.0 * G * height) - speed) / G
            if released_at + fall_s > t1:
                break
            self.parcels.popleft()
            self.in_flight_kg -= mass
            self.landed_kg += mass
            momentum += mass * (speed + G * fall_s)
        if not self.parcels:
            self.in_flight_kg = 0.0  # no rounding residue once nothing is in the air
        # impact: the landed momentum passes to the platform through a first-order relaxation
        self.impulse_n_s += momentum
        if c.impact_relax_ms > 0.0:
            passed = self.impulse_n_s * (1.0 - math.exp(-STEP_S * 1000.0 / c.impact_relax_ms))
        else:
            passed = self.impulse_n_s
        self.impulse_n_s -= passed
        self.impact_n = passed / STEP_S
        # platform
        self.time = t1
        test_kg = self.test_weight_kg()
        load_n = (self.landed_kg + test_kg) * G + self.impact_n
        if self.shake_kg:
            load_n += self.shake_kg * G * math.sin(2.0 * math.pi * self.shake_hz * t1)
        if c.rigid:
            self.y, self.vy = load_n, 0.0
            return
        mass = c.platform_kg + self.landed_kg + test_kg
        h = STEP_S / PLATFORM_SUBSTEPS
        for _ in range(PLATFORM_SUBSTEPS):  # semi-implicit Euler on the force y = k x
            self.vy += (load_n - self.y - self.damper * self.vy / self.stiffness) * self.stiffness / mass * h
            self.y += self.vy * h

    def cell_force_n(self):
        """Force on the load cell above the empty scale (the spring's, or the rigid load's)."""
        return self.y

    def ring_n(self):
        """How far the platform swings about the load it carries now (the amplitude of its free
        oscillation from where it is and how fast it moves), in newtons on the load cell."""
        c = self.config
        if c.rigid:
            return 0.0
        mass = c.platform_kg + self.landed_kg + self.test_weight_kg()
        load_n = (self.landed_kg + self.test_weight_kg()) * G + self.impact_n
        return math.hypot(self.y - load_n, self.vy * math.sqrt(mass / self.stiffness))

    def sample(self):
        """The ADC's reading of this instant: (int32 counts, status bits)."""
        c = self.config
        kg = self.cell_force_n() / G
        counts = c.offset_counts + c.counts_per_kg * kg
        if c.noise_d > 0.0:
            counts += c.noise_d * c.d_g / 1000.0 * c.counts_per_kg * self.rng.gauss(0.0, 1.0)
        status = 0
        if kg > 1.1 * c.capacity_kg or counts > INT32_MAX:
            status |= STATUS_OVERLOAD
        if kg < -0.02 * c.capacity_kg or counts < INT32_MIN:
            status |= STATUS_UNDERLOAD
        return max(INT32_MIN, min(INT32_MAX, int(round(counts)))), status

    def on_scale_kg(self):
        return self.landed_kg + self.test_weight_kg()


class ProtocolError(Exception):
    pass


@dataclass
class Answer:
    command: str
    lines: list
    sent_jiffy: int
    answered_jiffy: int

    @property
    def final(self):
        return self.lines[-1] if self.lines else ""

    @property
    def ok(self):
        return self.final == "OK"

    def line_starting(self, prefix):
        return next((l for l in self.lines if l.startswith(prefix)), None)


@dataclass
class CommandRecord:
    jiffy: int
    counter: int
    command: int
    delay_100us: int


class OutsidePlant:
    """The plant on udp with dynweigh-fw as a subprocess (--console stdio), in lockstep: sample k
    goes out, the 0x220 carrying counter k must come back, its command is applied after its
    delay, the physics runs 10 ms at 1 ms, then sample k+1."""

    def __init__(self, fw, config=None, nvm=None, fw_args=(), answer_timeout_s=3.0, echo=True,
                 startup_timeout_s=10.0):
        self.config = config or PlantConfig()
        self.physics = Physics(self.config)
        self.echo = echo
        self.answer_timeout_s = answer_timeout_s
        self.jiffy = 0
        self.protocol_errors = []
        self.answers_received = 0
        self.commands = []            # every 0x220, in order (CommandRecord)
        self.status_frames = {}       # counter -> (weight_100mg, state, valve) from 0x181
        self.fault_jiffies = []       # jiffies whose 0x181 said fault
        self.heartbeats = []          # (jiffy, nmt state) of the indicator
        self.fw_stopped = False       # the indicator said NMT stopped: it is leaving
        self.output = []              # (jiffy, line) from the indicator's stdout
        self._cursor = 0              # first output line not yet claimed by an answer
        self._partial = ""
        self.stderr_text = ""
        self.input_closed = False
        self.transcript = []          # ("> line" or "< line", jiffy)

        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.sock.bind(("127.0.0.1", 0))
        self.plant_port = self.sock.getsockname()[1]
        probe = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        probe.bind(("127.0.0.1", 0))
        self.fw_port = probe.getsockname()[1]
        probe.close()
        command = [fw, "--plant", f"can:udp:{self.fw_port}@127.0.0.1:{self.plant_port}", "--console", "stdio"]
        if nvm:
            command += ["--nvm", nvm]
        command += list(fw_args)
        self.fw_command = command
        self.process = subprocess.Popen(command, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                        stderr=subprocess.PIPE)
        os.set_blocking(self.process.stdout.fileno(), False)
        os.set_blocking(self.process.stderr.fileno(), False)
        self._wait_for_indicator(startup_timeout_s)

    # --- wire -------------------------------------------------------------------------------------
    def _send(self, can_id, data):
        self.sock.sendto(pack_frame(can_id, data), ("127.0.0.1", self.fw_port))

    def _wait_for_indicator(self, timeout_s):
        """Before the first sample: any frame from the indicator (its boot-up or heartbeat)
        proves its socket is bound, so sample 0 is not lost."""
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline:
            ready, _, _ = select.select([self.sock], [], [], 0.05)
            self._drain_pipes()
            if ready:
                self._handle(self.sock.recv(64), expected=None)
                return
            if self.process.poll() is not None:
                raise ProtocolError(f"dynweigh-fw exited {self.process.returncode} before its first frame: "
                                    f"{self.stderr_text.strip()}")
        raise ProtocolError(f"no frame from dynweigh-fw within {timeout_s} s of its start")

    def _handle(self, datagram, expected):
        """One frame from the indicator; returns the 0x220 record when it answers `expected`."""
        frame = unpack_frame(datagram)
        if frame is None:
            self.protocol_errors.append(f"jiffy {self.jiffy}: a datagram of {len(datagram)} bytes, not a can_frame")
            return None
        can_id, data = frame
        if can_id == ID_VALVE_COMMAND:
            if len(data) != 4:
                self.protocol_errors.append(f"jiffy {self.jiffy}: 0x220 with DLC {len(data)}, not 4")
                return None
            command, delay, counter = struct.unpack("<BBH", data)
            if expected is None or counter != expected:
                self.protocol_errors.append(
                    f"jiffy {self.jiffy}: 0x220 for counter {counter} while "
                    + ("no sample was waiting" if expected is None else f"waiting for counter {expected}")
                    + " (a second answer, or one for the wrong sample)")
                return None
            if command > 2 or delay > 99:
                self.protocol_errors.append(f"jiffy {self.jiffy}: 0x220 command {command} delay {delay} out of range")
            return CommandRecord(self.jiffy, counter, min(command, 2), min(delay, 99))
        if can_id == ID_STATUS and len(data) == 8:
            weight, state, valve, counter = struct.unpack("<iBBH", data)
            self.status_frames[counter] = (weight, state, valve)
            if state == 3:
                self.fault_jiffies.append(self.jiffy)
        elif can_id == ID_HEARTBEAT + NODE_INDICATOR and len(data) == 1:
            self.heartbeats.append((self.jiffy, data[0]))
            if data[0] == NMT_STOPPED:
                self.fw_stopped = True
        return None

    def _drain_pipes(self):
        for stream, is_stdout in ((self.process.stdout, True), (self.process.stderr, False)):
            while True:
                try:
                    chunk = os.read(stream.fileno(), 65536)
                except BlockingIOError:
                    break
                if not chunk:
                    break
                text = chunk.decode("utf-8", "replace")
                if not is_stdout:
                    self.stderr_text += text
                    continue
                self._partial += text
                *lines, self._partial = self._partial.split("\n")
                for line in lines:
                    line = line.rstrip("\r")
                    self.output.append((self.jiffy, line))
                    self.transcript.append((self.jiffy, "< " + line))
                    if self.echo:
                        print(f"[{self.jiffy * JIFFY_S:8.2f} s] < {line}", flush=True)

    def _await_answer(self, counter):
        """Waits for the 0x220 answering `counter`: the record, or None once the indicator has
        left (exited, or said NMT stopped); a silent indicator still running is a protocol error."""
        deadline = time.monotonic() + self.answer_timeout_s
        while True:
            remaining = deadline - time.monotonic()
            ready, _, _ = select.select([self.sock], [], [], max(0.0, min(remaining, 0.05)))
            if ready:
                record = self._handle(self.sock.recv(64), expected=counter)
                if record:
                    return record
                continue
            if self.fw_stopped or self.process.poll() is not None:
                self._drain_pipes()
                return None
            if remaining <= 0.0:
                self._drain_pipes()
                raise ProtocolError(
                    f"sample {self.jiffy} (counter {counter}, t={self.jiffy * JIFFY_S:.2f} s) unanswered for "
                    f"{self.answer_timeout_s} s: no 0x220 with its counter while dynweigh-fw runs"
                    + (" (its console input is open and no line is pending: does it block reading stdin?)"
                       if not self.input_closed else ""))

    # --- lockstep ---------------------------------------------------------------------------------
    def tick(self):
        """One jiffy: sample out, answer in, command applied, 10 ms of physics. False once the
        indicator has left."""
        if self.fw_stopped or self.process.poll() is not None:
            return False
        counter = self.jiffy & 0xFFFF
        counts, status = self.physics.sample()
        self._send(ID_VALVE_FEEDBACK, struct.pack("<BB", self.physics.valve.feedback(), 0))
        self._send(ID_SAMPLE, struct.pack("<iHBB", counts, counter, status, 0))
        if self.jiffy % 10 == 0:
            for node in (NODE_LOAD_CELL, NODE_VALVE):
                self._send(ID_HEARTBEAT + node, bytes([NMT_OPERATIONAL]))
        self.last_counts = counts
        record = self._await_answer(counter)
        self._drain_pipes()
        if record is None:
            return False
        self.answers_received += 1
        self.commands.append(record)
        self.physics.valve.command(record.command, self.physics.time + record.delay_100us * 1e-4)
        for _ in range(STEPS_PER_JIFFY):
            self.physics.step()
        self.jiffy += 1
        return True

    def run(self, seconds):
        for _ in range(int(round(seconds / JIFFY_S))):
            if not self.tick():
                return False
        return True

    def run_until(self, predicate, max_seconds):
        """Ticks until predicate() holds; False if max_seconds of plant time pass first."""
        for _ in range(int(round(max_seconds / JIFFY_S))):
            if predicate():
                return True
            if not self.tick():
                return predicate()
        return predicate()

    # --- operator ---------------------------------------------------------------------------------
    def send(self, line):
        """Types one console line (it reaches the indicator before the next sample)."""
        self.transcript.append((self.jiffy, "> " + line))
        if self.echo:
            print(f"[{self.jiffy * JIFFY_S:8.2f} s] > {line}", flush=True)
        self.process.stdin.write((line + "\n").encode())
        self.process.stdin.flush()

    def close_input(self):
        if not self.input_closed:
            self.input_closed = True
            self.process.stdin.close()

    def _answer_end(self):
        for i in range(self._cursor, len(self.output)):
            line = self.output[i][1]
            if line == "OK" or line.startswith("ERR "):
                return i
        return None

    def wait_answer(self, command="", max_seconds=60.0, sent_jiffy=None):
        """The indicator's whole answer to the oldest unanswered line (up to OK or ERR)."""
        sent = self.jiffy if sent_jiffy is None else sent_jiffy
        if not self.run_until(lambda: self._answer_end() is not None, max_seconds):
            return None
        end = self._answer_end()
        lines = [l for _, l in self.output[self._cursor:end + 1]]
        answered = self.output[end][0]
        self._cursor = end + 1
        return Answer(command, lines, sent, answered)

    def command(self, line, max_seconds=60.0):
        sent = self.jiffy
        self.send(line)
        return self.wait_answer(line, max_seconds, sent)

    def put_weight(self, kg, ramp_s=0.5):
        """Sets a test weight down (on top of what is there) along a ramp of ramp_s."""
        self.physics.set_test_weight(self.physics.weight_to_kg + kg, ramp_s)
        if self.echo:
            print(f"[{self.jiffy * JIFFY_S:8.2f} s] operator: sets {kg} kg down over {ramp_s} s", flush=True)

    def take_weight(self, ramp_s=0.5):
        self.physics.set_test_weight(0.0, ramp_s)
        if self.echo:
            print(f"[{self.jiffy * JIFFY_S:8.2f} s] operator: takes the test weights off over {ramp_s} s", flush=True)

    def shake(self, amplitude_kg, hz):
        self.physics.shake_kg, self.physics.shake_hz = amplitude_kg, hz
        if self.echo:
            print(f"[{self.jiffy * JIFFY_S:8.2f} s] operator: shakes the platform +-{amplitude_kg} kg at {hz} Hz"
                  if amplitude_kg else f"[{self.jiffy * JIFFY_S:8.2f} s] operator: stops shaking", flush=True)

    # --- what the indicator did --------------------------------------------------------------------
    def status_state(self, counter):
        frame = self.status_frames.get(counter & 0xFFFF)
        return INDICATOR_STATES.get(frame[1], str(frame[1])) if frame else None

    def open_commands_since(self, jiffy):
        return [r for r in self.commands if r.jiffy >= jiffy and r.command != 0]

    def finish(self, max_seconds=120.0, stop_plant=True):
        """End of input: the command in progress finishes and the indicator leaves. Ticks until it
        has (at most max_seconds of plant time); then tells it the plant stops and returns its exit
        status (None if it had to be killed)."""
        self.close_input()
        for _ in range(int(round(max_seconds / JIFFY_S))):
            if not self.tick():
                break
        if stop_plant:
            try:
                self._send(ID_HEARTBEAT + NODE_LOAD_CELL, bytes([NMT_STOPPED]))
            except OSError:
                pass
        try:
            self.process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()
            self._drain_pipes()
            return None
        self._drain_pipes()
        return self.process.returncode

    def close(self):
        if self.process.poll() is None:
            self.process.terminate()
            try:
                self.process.wait(5)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
        self._drain_pipes()
        self.sock.close()

    def heartbeat_gaps_ok(self, first_jiffy=0, last_jiffy=None, every=10, slack=2):
        """The indicator's operational heartbeat at least every `every` jiffies (+ slack)."""
        last = self.jiffy if last_jiffy is None else last_jiffy
        beats = [j for j, s in self.heartbeats if s == NMT_OPERATIONAL and first_jiffy <= j <= last]
        points = [first_jiffy] + beats + [last]
        return max(b - a for a, b in zip(points, points[1:])) <= every + slack

    def summary(self):
        p = self.physics
        return {
            "jiffies": self.jiffy,
            "answers": self.answers_received,
            "protocol_errors": len(self.protocol_errors),
            "fw_heartbeats": len(self.heartbeats),
            "released_kg": f"{p.released_kg:.4f}",
            "landed_kg": f"{p.landed_kg:.4f}",
            "in_flight_kg": f"{p.in_flight_kg:.4f}",
            "silo_kg": f"{p.silo_kg:.4f}",
        }

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def plant_config_from_args(args):
    config = PlantConfig()
    for f in fields(PlantConfig):
        value = getattr(args, f.name, None)
        if value is not None:
            setattr(config, f.name, value)
    return config


def add_config_arguments(parser):
    for f in fields(PlantConfig):
        if f.type in (bool, "bool"):
            parser.add_argument(f"--{f.name.replace('_', '-')}", dest=f.name, type=int, choices=(0, 1),
                                help=f"0 or 1 (default {int(f.default)})")
        else:
            kind = int if f.type in (int, "int") else float
            parser.add_argument(f"--{f.name.replace('_', '-')}", dest=f.name, type=kind,
                                help=f"default {f.default}")


def run_steps(plant, steps):
    """The CLI's operator: `send <line>`, `wait <s>`, `put <kg> [ramp s]`, `take [ramp s]`,
    `shake <kg> <hz>`, `still`, `stick`."""
    for step in steps:
        verb, _, rest = step.partition(" ")
        if verb == "send":
            answer = plant.command(rest)
            if answer is None:
                print(f"no answer to '{rest}' within 60 s", file=sys.stderr)
                return False
        elif verb == "wait":
            if not plant.run(float(rest)):
                return False
        elif verb == "put":
            parts = rest.split()
            plant.put_weight(float(parts[0]), float(parts[1]) if len(parts) > 1 else 0.5)
        elif verb == "take":
            plant.take_weight(float(rest) if rest else 0.5)
        elif verb == "shake":
            amplitude, hz = rest.split()
            plant.shake(float(amplitude), float(hz))
        elif verb == "still":
            plant.shake(0.0, 0.0)
        elif verb == "stick":
            plant.physics.valve.stuck = True
        else:
            raise SystemExit(f"outside_plant: unknown step '{step}'")
    return True


def main():
    parser = argparse.ArgumentParser(
        description="An outside plant (silo, valve, falling stream, ringing platform, load cell) for "
                    "dynweigh-fw over the udp CAN transport, with an operator who follows --do steps.")
    parser.add_argument("--fw", required=True, help="path of dynweigh-fw")
    parser.add_argument("--nvm", help="passed to dynweigh-fw")
    parser.add_argument("--do", action="append", default=[], metavar="STEP",
                        help="send <line> | wait <s> | put <kg> [ramp_s] | take [ramp_s] | shake <kg> <hz> | "
                             "still | stick (repeatable, in order)")
    parser.add_argument("--answer-timeout", type=float, default=3.0, help="s of wall time per 0x220")
    add_config_arguments(parser)
    args = parser.parse_args()
    config = plant_config_from_args(args)
    print(config.describe())
    print(f"beverloo_kg_s={Physics(config).full_flow_kg_s():.4f} outflow_m_s={Physics(config).outflow_speed():.4f}")
    plant = OutsidePlant(args.fw, config, nvm=args.nvm, answer_timeout_s=args.answer_timeout)
    try:
        ok = run_steps(plant, args.do)
        rc = plant.finish()
    except ProtocolError as e:
        print(f"protocol_error={e}")
        ok, rc = False, None
    finally:
        plant.close()
    for key, value in plant.summary().items():
        print(f"{key}={value}")
    for error in plant.protocol_errors:
        print(f"protocol: {error}")
    print(f"fw_exit={rc}")
    if plant.stderr_text.strip():
        print("--- dynweigh-fw stderr ---\n" + plant.stderr_text.strip())
    return 0 if ok and rc == 0 and not plant.protocol_errors else 1


if __name__ == "__main__":
    sys.exit(main())
