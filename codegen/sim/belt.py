"""A simulated belt for verify: its travel over time, the encoder's raw counter and the parts on it."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

TRIGGER_S = 0.01  # the camera's trigger pulse (s): longer than a controller's input cycle


@dataclass(frozen=True)
class Belt:
    """The belt's travel s(t) (mm downstream since the program started) and its encoder.

    speed_mm_s: the mean speed; wobble: the share by which the speed swings, sinusoidally with period
    period_s (0: constant); counts_per_mm: signed (negative: the counter runs down as the belt travels);
    counter_bits: the counter's width (it rolls over at 2**bits); start_count: its raw value at t = 0; stops: the
    intervals (when it stops, how long it stands, s) in which the belt stands: it stops and starts again at once,
    its motion between them as if the standing time were cut out of the clock."""

    speed_mm_s: float
    counts_per_mm: float
    counter_bits: int = 32
    start_count: int = 0
    wobble: float = 0.0
    period_s: float = 4.0
    stops: tuple[tuple[float, float], ...] = ()

    def running_s(self, t: float) -> float:
        """How long the belt has run by t: t less the time it stood before t."""
        return t - sum(min(max(t - start, 0.0), length) for start, length in self.stops)

    def standing(self, t: float) -> bool:
        return any(start <= t < start + length for start, length in self.stops)

    def travel_mm(self, t: float) -> float:
        """s(t) = v r + v wobble T / (2 pi) (1 - cos(2 pi r / T)), r the time it has run: the speed
        v (1 + wobble sin(2 pi r / T)) while it runs."""
        r = self.running_s(t)
        w = 2.0 * math.pi / self.period_s
        return self.speed_mm_s * (r + self.wobble * (1.0 - math.cos(w * r)) / w)

    def speed_at(self, t: float) -> float:
        if self.standing(t):
            return 0.0
        return self.speed_mm_s * (1.0 + self.wobble * math.sin(2.0 * math.pi * self.running_s(t) / self.period_s))

    def unwrapped_count(self, t: float) -> int:
        """The counter as if it had no width: the start count plus whole counts of travel."""
        return self.start_count + math.floor(self.counts_per_mm * self.travel_mm(t))

    def count(self, t: float) -> int:
        """The raw counter at t: unwrapped_count reduced to the counter's width (two's complement for
        32 bits, as a signed register holds it; unsigned for 16 and 24)."""
        span = 2**self.counter_bits
        raw = self.unwrapped_count(t) % span
        if self.counter_bits == 32 and raw >= span // 2:
            raw -= span
        return raw

    def time_at(self, travel_mm: float) -> float:
        """The first t >= 0 with s(t) = travel_mm (s never decreases: the speed stays positive while it runs)."""
        if travel_mm <= 0.0:
            return 0.0
        stood = sum(length for _start, length in self.stops)
        low, high = 0.0, travel_mm / (self.speed_mm_s * (1.0 - abs(self.wobble))) + 1.0 + stood
        for _ in range(80):
            mid = 0.5 * (low + high)
            low, high = (mid, high) if self.travel_mm(mid) < travel_mm else (low, mid)
        return high


@dataclass(frozen=True)
class Part:
    """A part the camera saw: when it crossed the camera's line, across the belt (x) and its top (z),
    belt frame mm; seq: its number in the queue (1 first)."""

    seq: int
    seen_s: float
    x: float
    z: float


def part_y(belt: Belt, part: Part, camera_y: float, t: float) -> float:
    """Where a part is along the belt (belt frame y, mm) at t: the camera's line plus the travel since."""
    return camera_y + belt.travel_mm(t) - belt.travel_mm(part.seen_s)


def part_pose(belt2base: np.ndarray, belt: Belt, part: Part, camera_y: float, t: float, grip: np.ndarray):
    """The gripper's pose on the part at t (base frame, 4x4): the belt frame . Trans(x, y(t), z) . grip."""
    place = np.eye(4)
    place[:3, 3] = (part.x, part_y(belt, part, camera_y, t), part.z)
    return belt2base @ place @ grip


@dataclass(frozen=True)
class RobotEncoder:
    """The controller's own encoder input on the same belt: the same counts from another zero (it was
    enabled at another moment than the PLC's counter), counted backwards where the program takes the wiring's A
    as B (sign -1), not at all where it reads inputs the encoder is not wired to (sign 0); scale: its counts per count
    of the PLC's (a decoder counting other edges)."""

    belt: Belt
    zero: int
    sign: int = 1
    scale: float = 1.0  # its counts per count of the PLC's counter (1: the same edges decoded)

    def unwrapped_count(self, t: float) -> int:
        return self.sign * round(self.scale * self.belt.unwrapped_count(t)) + self.zero


@dataclass(frozen=True)
class UnitSettings:
    """A controller's tracking option's configuration of a belt as a mechanical unit: its name, counts per metre
    (a whole number), its base frame (4x4 in the robot's base: at the sync point, x along the travel), the
    queue tracking distance (sync point to the start window's start, mm), the start window's width, the minimum
    distance between two queued objects (a sync closer to the last queued one is ignored) and the tracking
    range's end (mm past the sync point)."""

    name: str
    counts_per_m: int
    frame: np.ndarray = field(compare=False)
    start_mm: float
    width_mm: float
    min_gap_mm: float
    max_mm: float
    remove_all: str | None = None  # the encoder interface's output that empties the queue of objects not connected
    axis: int = 7  # the unit's logical axis: 7..12, its position in a robtarget's / jointtarget's eax_a..eax_f


@dataclass
class TrackingUnit:
    """The belt as a mechanical unit of the controller (an encoder interface with a sync input at the camera's
    line): the encoder counts up as the belt travels (|counts per mm| a count each); each part the camera sees
    is a sync, queued with the count then unless it comes within min_gap_mm of the last queued one. An object
    is in the queue from its sync until it leaves the start window ([start_mm, start_mm + width_mm] past the
    sync point), is connected, or dropped. Connected, its position is its travel since its sync by the
    configured counts per metre (0 with none connected). Records what happened to each part for the judge.
    Its sync input is its own device, apart from the PLC's queue: extra_syncs are syncs no part made (a stray or
    double pulse: an object the PLC does not queue), missed the numbers of parts whose sync it never saw."""

    settings: UnitSettings
    belt: Belt
    parts: list
    active: bool = False
    connected: Part | None = None
    done: set = field(default_factory=set)  # connected (and later dropped) parts' numbers
    connections: list = field(default_factory=list)  # (seq, t) of each connection
    drops: list = field(default_factory=list)  # (seq, t)
    lost_waiting: list = field(default_factory=list)  # (seq, t): lost while the program waited for it
    flushes: list = field(default_factory=list)  # moments the queue was emptied (remove_all set)
    extra_syncs: tuple = ()
    missed: frozenset = frozenset()
    _queue: list | None = None

    @property
    def name(self) -> str:
        return self.settings.name

    def board(self, t: float) -> int:
        return math.floor(abs(self.belt.counts_per_mm) * self.belt.travel_mm(t))

    def queued(self) -> list:
        """The parts whose sync the unit took (oldest first), and each one's count then."""
        if self._queue is None:
            out, last = [], None
            per_mm = self.settings.counts_per_m / 1000.0
            stray = [Part(-k, seen, math.nan, math.nan) for k, seen in enumerate(self.extra_syncs, start=1)]
            syncs = [p for p in self.parts if p.seq not in self.missed] + stray
            for part in sorted(syncs, key=lambda p: p.seen_s):
                count = self.board(part.seen_s)
                if last is None or (count - last) / per_mm >= self.settings.min_gap_mm:
                    out.append((part, count))
                    last = count
            self._queue = out
        return self._queue

    def ignored(self) -> set:
        """The numbers of the parts whose sync came too close to the last queued one."""
        taken = {p.seq for p, _ in self.queued()}
        return {p.seq for p in self.parts if p.seq not in taken and p.seq not in self.missed}

    def position_of(self, count: int, t: float) -> float:
        return (self.board(t) - count) / (self.settings.counts_per_m / 1000.0)

    def _time_at(self, count: int, position_mm: float) -> float:
        """When an object synced at `count` has travelled position_mm by the unit's reckoning."""
        counts = math.ceil(position_mm * self.settings.counts_per_m / 1000.0) + count
        return self.belt.time_at(counts / abs(self.belt.counts_per_mm))

    def position_mm(self, t: float) -> float:
        if self.connected is None:
            return 0.0
        count = next(c for p, c in self.queued() if p is self.connected)
        return self.position_of(count, t)

    def connect(self, t: float, rel_mm: float = 0.0, until: float = math.inf) -> tuple[int | None, float, bool | None]:
        """WaitWObj at t: the oldest object still in the queue, connected once it is inside the start window (and
        rel_mm past the sync point): (its part's number, when, True); (number, when, False): it left the start
        window first (lost); (None, inf, False): no object will come; (None, until, None): none connected by until
        (the queue left as it was)."""
        end = self.settings.start_mm + self.settings.width_mm
        for part, count in self.queued():
            if part.seq in self.done or self._time_at(count, end) <= max(t, part.seen_s):
                continue  # connected before, or out of the start window already (dropped from the queue)
            due = max(t, part.seen_s, self._time_at(count, max(self.settings.start_mm, rel_mm)))
            if rel_mm > end:
                lost = max(t, self._time_at(count, end))
                if lost > until:
                    return None, until, None
                self.done.add(part.seq)
                self.lost_waiting.append((part.seq, lost))
                return part.seq, lost, False
            if due > until:
                return None, until, None
            self.connected = part
            self.done.add(part.seq)
            self.connections.append((part.seq, due))
            return part.seq, due, True
        return (None, math.inf, False) if until == math.inf else (None, until, None)

    def remove_all(self, t: float) -> None:
        """The queue emptied at t (its remove_all signal): every object synced by then and not connected leaves it."""
        self.flushes.append(t)
        for part, _count in self.queued():
            if part.seen_s <= t and part is not self.connected:
                self.done.add(part.seq)

    def drop(self, t: float) -> None:
        if self.connected is not None:
            self.drops.append((self.connected.seq, t))
        self.connected = None


@dataclass
class BeltLine:
    """The belt, its camera and the PLC's part queue beside the controller, a device of Program.run.

    The camera sees each part cross its line at part.seen_s; the PLC queues it with the encoder's count
    then and presents the oldest one the program has not taken (its number, the count, x and z, through
    the target's bus: codegen/sim/bus.py). The program takes it by writing its number back; then the
    next is presented. With the queue empty and no part to come, the line's cycle stop turns on (not before
    stop_s).
    taken: seq -> when the program took it."""

    belt: Belt
    parts: list
    bus: object
    encoder_index: int = 0
    robot_zero: int = 0  # where the controller's own encoder counts from, against the PLC's counter
    robot_scale: float = 1.0  # the controller's own encoder's counts per count of the PLC's counter
    unlatched: frozenset = frozenset()  # the parts whose trigger pulse the controller's input missed (numbers)
    wiring: tuple[int, int] | None = None  # the inputs the encoder's A and B are wired to (None: as the program says)
    taken: dict = field(default_factory=dict)
    unit: TrackingUnit | None = None  # the belt as the controller's mechanical unit (its tracking option)
    latency_s: float = 0.0  # how old the counter's count is when the program reads it (PLC and fieldbus), at least
    # the PLC copies the counter's count once a cycle of age_cycle_s (at age_phase_s + k cycles): between its copies the
    # count the program reads grows older, by up to a cycle more than latency_s (0: a count always latency_s old)
    age_cycle_s: float = 0.0
    age_phase_s: float = 0.0
    trigger: str | None = None  # the controller's input the camera's trigger is wired to (a pulse per part)
    stop_s: float = 0.0  # the line's cycle stop not before this (s): with no part to come, the program waits till then
    # the controller beside the belt: each sleep of the program (a pass of a polling loop) ends this much later than it
    # asks (the pass's statements, the interpreter's cycle): a program that counts its passes as exact sleeps
    # measures the belt's speed wrong (Machine.elapse)
    sleep_overhead_s: float = 0.0
    pulses: tuple = ()  # moments the camera's trigger pulses with no part queued (a double pulse, a dropped part)
    _presented: int = 0
    _stopped: bool = False
    _outputs_seen: int = 0

    def encoder(self, index: int, a: int | None = None, b: int | None = None):
        """The encoder on the controller's decoder `index`, read through the inputs a (A) and b (B)."""
        if index != self.encoder_index:
            return None
        if self.wiring is None or (a, b) == tuple(self.wiring):
            return RobotEncoder(self.belt, self.robot_zero, 1, self.robot_scale)
        if (b, a) == tuple(self.wiring):
            return RobotEncoder(self.belt, self.robot_zero, -1, self.robot_scale)
        return RobotEncoder(self.belt, self.robot_zero, 0)

    def mechanical_unit(self, name: str) -> TrackingUnit | None:
        """The belt as the controller's mechanical unit of this name, where its tracking option is configured."""
        return self.unit if self.unit is not None and self.unit.name.upper() == name.upper() else None

    def live(self, name: str, t: float):
        if name == self.trigger:  # on for TRIGGER_S from each part's moment at the camera's line
            moments = [*(part.seen_s for part in self.parts if part.seq not in self.unlatched), *self.pulses]
            return any(seen <= t < seen + TRIGGER_S for seen in moments)
        return self.bus.live(self.belt, name, max(0.0, t - self.age_s(t)))

    def age_s(self, t: float) -> float:
        """How old what the program reads from the PLC at t is: latency_s, and the time since the PLC's last copy."""
        if self.age_cycle_s <= 0.0:
            return self.latency_s
        return self.latency_s + (t - self.latency_s - self.age_phase_s) % self.age_cycle_s

    def _flush(self, machine) -> None:
        """The unit's queue emptied at each rise of its remove_all output the program set since the last look."""
        name = None if self.unit is None else self.unit.settings.remove_all
        if name is None:
            return
        outputs = machine.trace.outputs
        for event in outputs[self._outputs_seen :]:
            if event.name == name and event.value:
                self.unit.remove_all(event.time)
        self._outputs_seen = len(outputs)

    def _next(self):
        return self.parts[self._presented] if self._presented < len(self.parts) else None

    def next_time(self, machine) -> float | None:
        part = self._next()
        if self._presented and self._presented not in self.taken:
            return None
        if part is None:  # the line's cycle stop, when it is still to come
            return None if self._stopped or machine.clock >= self.stop_s else self.stop_s
        return max(part.seen_s, machine.clock)

    def on_wait(self, machine, where: str) -> bool:
        self._flush(machine)
        if self._presented and self._presented not in self.taken and self.bus.ack(machine) == self._presented:
            self.taken[self._presented] = machine.clock
        if self._presented and self._presented not in self.taken:
            return False  # the program has not taken the part on show
        part = self._next()
        if part is None:
            if not self._stopped and machine.clock >= self.stop_s:
                self._stopped = True
                self.bus.stop(machine)
                return True
            return False
        if machine.clock < part.seen_s:
            return False
        count = self.belt.count(part.seen_s)
        self.bus.present(machine, {"count": count, "x": part.x, "z": part.z, "seq": part.seq})
        self._presented = part.seq
        return True
