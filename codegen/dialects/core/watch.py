"""Inputs that change while the arm moves: the tool's path in time, inputs read each controller cycle, edges."""

# A controller reads its inputs once per cycle (targets/<t>.toml signal_cycle_s): an input that changes
# while the arm moves (a beam the tool crosses) is seen at the first cycle after it changed, and what the
# controller latches there (an interrupt's latched position, a search's point, a thread's reading of the
# pose) is the tool's pose at that cycle. Devices that switch with the tool's pose (codegen/sim/beam_station.py) answer
# switch(name, t, flange2base) for each cycle in increasing time: their state may depend on the previous
# cycle (hysteresis, noise), so an input's history is evaluated once, forward, and shared by every reader.

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from codegen.dialects.core.values import RunError

EDGES = ("rising", "falling", "both", "every")  # "every": called each cycle (a UR thread's sync())


class Path:
    """The TCP's path of one move (base frame): a straight line, or the circle through start, via and end
    (the controllers' circular move), with the orientation of the start held (fixed-orientation moves:
    the circular moves here keep it; a linear move's end orientation is reached at its end)."""

    def __init__(self, start: np.ndarray, end: np.ndarray, via: np.ndarray | None = None) -> None:
        self.start, self.end, self.via = start, end, via
        p0, p2 = start[:3, 3], end[:3, 3]
        if via is None:
            self.length = float(np.linalg.norm(p2 - p0))
            self.circle = None
            return
        p1 = via[:3, 3]
        a, b = p1 - p0, p2 - p0
        normal = np.cross(a, b)
        nn = float(normal @ normal)
        if nn < 1e-12:
            raise RunError("a circular move's start, circle point and end lie on one line")
        centre = p0 + (np.dot(a, a) * np.cross(b, normal) + np.dot(b, b) * np.cross(normal, a)) / (2.0 * nn)
        radius = float(np.linalg.norm(p0 - centre))
        u = (p0 - centre) / radius
        w = normal / math.sqrt(nn)
        v = np.cross(w, u)  # the direction of travel at the start (towards the via point)
        sweep = math.atan2(float(np.dot(p2 - centre, v)), float(np.dot(p2 - centre, u))) % (2.0 * math.pi)
        self.circle = (centre, radius, u, v)
        self.sweep = sweep or 2.0 * math.pi
        self.length = radius * self.sweep

    def pose(self, s: float) -> np.ndarray:
        """The TCP at the share s (0..1) of the path's length."""
        out = self.start.copy()
        if self.circle is None:
            out[:3, 3] = self.start[:3, 3] + s * (self.end[:3, 3] - self.start[:3, 3])
            if s >= 1.0:
                out[:3, :3] = self.end[:3, :3]
            return out
        centre, radius, u, v = self.circle
        angle = s * self.sweep
        out[:3, 3] = centre + radius * (math.cos(angle) * u + math.sin(angle) * v)
        return out


@dataclass
class Segment:
    t0: float
    t1: float
    path: Path | None  # None: a move whose path the clock does not know (a joint move)
    tcp2flange: np.ndarray
    end: object  # the MoveEvent (its tcp2base is the pose after the move)
    flange2tcp: np.ndarray | None = None  # the inverse of tcp2flange (computed once)


@dataclass
class Watcher:
    """An input watched from t_on until t_off: handler(t, tcp2base) at each edge of the kind asked."""

    name: str
    edge: str
    handler: Callable[[float, np.ndarray | None], None]
    t_on: float
    t_off: float = math.inf
    done: float = -math.inf  # delivered up to this time
    last: bool | None = None


@dataclass
class _History:
    tick: int = -1  # the last cycle evaluated
    value: bool = False
    changes: list[tuple[int, bool]] = field(default_factory=list)  # (tick, value after it)


class Watching:
    """One run's moves in time and its switching inputs, for the machine (Machine.watching)."""

    def __init__(self, machine, cycle_s: float) -> None:
        self.machine = machine
        self.cycle = cycle_s
        self.segments: list[Segment] = []
        self.watchers: list[Watcher] = []
        self.histories: dict[str, _History] = {}
        self.devices = [d for d in machine.devices if hasattr(d, "switches")]
        self._delivering = False

    # --- the tool over time ---------------------------------------------------------------
    def record(self, t0: float, t1: float, start, event, via, tcp2flange, path=None) -> None:
        if path is None and start is not None and event.tcp2base is not None:
            path = Path(start, event.tcp2base, via)
        self.segments.append(Segment(t0, t1, path, tcp2flange.copy(), event, np.linalg.inv(tcp2flange)))

    def pose_at(self, t: float) -> tuple[np.ndarray | None, np.ndarray | None]:
        """(tcp2base, tcp2flange) at time t: on the path of the move under way, else where the last move
        ended (None before any move with a known pose)."""
        seg = self.segment_at(t)
        if seg is None:
            return None, None
        if t < seg.t1:
            if seg.path is None:
                return None, seg.tcp2flange
            return seg.path.pose((t - seg.t0) / (seg.t1 - seg.t0)), seg.tcp2flange
        self.machine.arm.resolve()
        return seg.end.tcp2base, seg.tcp2flange

    def cut(self, event, t: float, pose: np.ndarray) -> None:
        """The last move ends at t, at pose (Machine.cut_move): a straight path there."""
        segment = self.segments[-1]
        if segment.end is not event:
            raise RunError("a move can only be cut short while it is the last one recorded")
        start = segment.path.start if segment.path is not None else pose
        segment.path, segment.t1 = Path(start, pose), t

    def segment_at(self, t: float) -> Segment | None:
        """The last move that started by t."""
        for seg in reversed(self.segments):
            if seg.t0 <= t:
                return seg
        return None

    # --- inputs -----------------------------------------------------------------------------
    def handles(self, name: str) -> bool:
        return any(name in d.switches for d in self.devices)

    def _evaluate(self, name: str, tick: int) -> bool:
        history = self.histories.get(name)
        if history is None:  # first read: the cycles before it are nobody's concern
            history = self.histories[name] = _History(tick=tick - 1)
        for k in range(history.tick + 1, tick + 1):
            t = k * self.cycle
            tcp2base = self.pose_at(t)[0]
            flange2base = None if tcp2base is None else tcp2base @ self.segment_at(t).flange2tcp
            value = history.value
            for device in self.devices:
                answer = device.switch(name, k * self.cycle, flange2base)
                if answer is not None:
                    value = bool(answer)
                    break
            if value != history.value:
                history.changes.append((k, value))
                history.value = value
            history.tick = k
        if tick < history.tick:  # a cycle already evaluated: the value then
            value = False
            for k, v in history.changes:
                if k > tick:
                    break
                value = v
            return value
        return history.value

    def value(self, name: str, t: float) -> bool:
        """The input as the controller reads it at time t (its value at the last cycle up to t)."""
        return self._evaluate(name, math.floor(t / self.cycle + 1e-9))

    def edges(self, name: str, t0: float, t1: float, last: bool | None = None) -> list[tuple[float, bool]]:
        """The cycles in (t0, t1] at which the input changed, with its new value."""
        k0, k1 = math.floor(t0 / self.cycle + 1e-9), math.floor(t1 / self.cycle + 1e-9)
        before = self._evaluate(name, k0) if last is None else last
        self._evaluate(name, k1)
        out = []
        for k, v in self.histories[name].changes:
            if k0 < k <= k1 and v != before:
                out.append((k * self.cycle, v))
                before = v
        return out

    # --- watchers ---------------------------------------------------------------------------
    def watch(self, name: str, edge: str, handler) -> Watcher:
        if edge not in EDGES:
            raise ValueError(edge)
        clock = self.machine.clock
        last = None if edge == "every" else self.value(name, clock)  # "every": a cycle's call, no input read
        watcher = Watcher(name, edge, handler, clock, done=clock, last=last)
        self.watchers.append(watcher)
        return watcher

    def unwatch(self, watcher: Watcher) -> None:
        """Off from now: edges of the motion so far are delivered first, later ones never."""
        self.deliver()
        watcher.t_off = self.machine.clock
        if watcher in self.watchers:
            self.watchers.remove(watcher)

    def deliver(self) -> None:
        """Run the handlers of every edge up to the machine's clock, in time order (the handler sees the
        clock at the edge's cycle and the tool's pose there)."""
        if self._delivering or not self.watchers:
            return
        self._delivering = True
        machine = self.machine
        now = machine.clock
        try:
            events = []
            for order, w in enumerate(self.watchers):
                end = min(now, w.t_off)
                if end <= w.done:
                    continue
                if w.edge == "every":
                    k = math.floor(w.done / self.cycle + 1e-9) + 1
                    while k * self.cycle <= end + 1e-12:
                        events.append((k * self.cycle, order, w, None))
                        k += 1
                else:
                    for t, value in self.edges(w.name, w.done, end, w.last):
                        w.last = value
                        if w.edge == "both" or (w.edge == "rising") == value:
                            events.append((t, order, w, value))
                w.done = end
            events.sort(key=lambda e: (e[0], e[1]))
            for t, _order, w, _value in events:
                if w.t_off <= t:
                    continue
                machine.clock = t
                w.handler(t, self.pose_at(t)[0])
                machine.step("<interrupt>")
        finally:
            machine.clock = max(now, machine.clock)
            self._delivering = False
