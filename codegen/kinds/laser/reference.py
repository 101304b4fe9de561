"""The laser TCP program's float64 reference: the same moves, every beam edge solved exactly on the path, the TCP."""

# What codegen/kinds/laser/program.py's programs do, with the edges where the geometry puts them (no controller
# cycle, no noise): each circle's edges found on the continuous circle (a scan in steps shorter than the pin
# is wide, then bisection), the search's on the continuous line; the sensors in their true frame (with the
# hysteresis the station has), the program's arithmetic in the frame the cell names. The controller sees an
# edge up to one cycle late (codegen/kinds/laser/verify.py's tolerances follow from that).

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from codegen.kinds.laser.program import DOWN, EDGES_PER_BEAM, circle_points
from codegen.kinds.laser.section import laser_of
from codegen.sim.beam_station import BeamStation

SCAN_MM = 0.1  # path step of the scan (an interruption is 2 pin radii long, at least 0.4 mm: never stepped over)
BISECT = 50


@dataclass(frozen=True)
class Expected:
    """edges: per circle, per beam, the S coordinate at each edge (beam X: y, beam Y: x); halt: the message
    key the program must stop with ("circle 1", "circle 2", "tilt", "no_tip", "too_far") or None; then the
    centres (e1, e2), the axis, the search's hits (down, up: S points), the TCP (flange frame)."""

    edges: tuple
    halt: str | None
    centres: tuple | None = None
    axis: np.ndarray | None = None
    hits: tuple | None = None
    tcp: np.ndarray | None = None


class Geometry:
    """The program's poses in the named S and what the sensors (in the true S) make of them."""

    def __init__(self, cell, station: BeamStation) -> None:
        self.laser = laser_of(cell)
        self.sensor2base = laser_of(cell).sensor_frame.matrix()
        self.guess = cell.robot.tool.tcp2flange
        self.station = station
        self.half = 0.5 * station.hysteresis

    def flange2base(self, point: np.ndarray) -> np.ndarray:
        """The flange with the guessed TCP at point (S) and the flange's z along S's -z."""
        flange2s = np.eye(4)
        flange2s[:3, :3] = DOWN
        flange2s[:3, 3] = point - DOWN @ self.guess[:3, 3]
        return self.sensor2base @ flange2s

    def on(self, beam: str, point: np.ndarray, was_on: bool) -> bool:
        """The beam's output after it was was_on: on when the pin is half the hysteresis past the beam, off
        when it has left by as much."""
        name = next(n for n, b in self.station.inputs.items() if b == beam)
        grow = self.half if was_on else -self.half
        return self.station.meets(name, self.flange2base(point), grow)

    def edges_along(self, beam: str, path, length: float) -> list[tuple[float, np.ndarray, bool]]:
        """(s, point, new value) of each switch along path(s), s in [0, length] mm."""
        steps = max(2, math.ceil(length / SCAN_MM))
        state = self.on(beam, path(0.0), False)
        out = []
        for i in range(1, steps + 1):
            s1 = length * i / steps
            if self.on(beam, path(s1), state) == state:
                continue
            low, high = length * (i - 1) / steps, s1
            for _ in range(BISECT):
                mid = 0.5 * (low + high)
                low, high = (low, mid) if self.on(beam, path(mid), state) != state else (mid, high)
            state = not state
            out.append((high, path(high), state))
        return out


def _circle(points: dict) -> tuple:
    """The full circle from start counterclockwise as path(s), its length."""
    start = np.array(points["start"])
    mid = np.array(points["mid"])
    centre = 0.5 * (start + mid)
    radius = float(np.linalg.norm(start[:2] - centre[:2]))
    angle0 = math.atan2(start[1] - centre[1], start[0] - centre[0])

    def path(s: float) -> np.ndarray:
        a = angle0 + s / radius
        return np.array([centre[0] + radius * math.cos(a), centre[1] + radius * math.sin(a), start[2]])

    return path, 2.0 * math.pi * radius


def tcp_from(cell, centres, axis, hits) -> np.ndarray:
    """The TCP from the contact (the hits' mean), the tip rho |ux| uz / sqrt(1 - ux^2) above the plane on the
    axis through S's origin (identity laser_tip_on_beam): guess + DOWN (tip - contact)."""
    contact = 0.5 * (np.asarray(hits[0]) + np.asarray(hits[1]))
    rim = laser_of(cell).pin_radius_mm * abs(axis[0]) * axis[2] / math.sqrt(1.0 - axis[0] ** 2)
    tip = axis * rim / axis[2]
    return cell.robot.tool.tcp2flange[:3, 3] + DOWN @ (tip - contact)


def from_measured(cell, edges: list[float], hits: list[float]) -> tuple:
    """The method's arithmetic in float64 on what a program latched (its 16 edges, its two hits): the
    centres, the axis and the TCP it must have computed from them (verify holds the program to these within
    its float32 arithmetic: a wrong formula shows even where the edges' timing hides it)."""
    n = EDGES_PER_BEAM
    centres = []
    for k in (0, 1):
        beam_x, beam_y = edges[2 * k * n : (2 * k + 1) * n], edges[(2 * k + 1) * n : (2 * k + 2) * n]
        centres.append(np.array([-sum(beam_y) / n, -sum(beam_x) / n]))
    d1, d2 = laser_of(cell).depths_mm
    slope = (centres[1] - centres[0]) / (d2 - d1)
    axis = np.array([slope[0], slope[1], 1.0]) / math.sqrt(1.0 + slope @ slope)
    tcp = tcp_from(cell, centres, axis, (hits[:3], hits[3:6]))
    return centres, axis, tcp


def expected(cell, station: BeamStation) -> Expected:
    """What the program must find with this station (its true pin and sensor frame, hysteresis, no noise)."""
    geo = Geometry(cell, station)
    laser = laser_of(cell)
    edges, centres = [], []
    for k in (0, 1):
        path, length = _circle(circle_points(laser, k))
        per_beam = []
        for beam, axis_index in (("x", 1), ("y", 0)):
            found = geo.edges_along(beam, path, length)
            per_beam.append(tuple(float(p[axis_index]) for _s, p, _v in found))
        edges.append(tuple(per_beam))
        if any(len(b) != EDGES_PER_BEAM for b in per_beam):
            return Expected(tuple(edges), f"circle {k + 1}")
        centres.append(np.array([-sum(per_beam[1]) / EDGES_PER_BEAM, -sum(per_beam[0]) / EDGES_PER_BEAM]))
    d1, d2 = laser.depths_mm
    slope = (centres[1] - centres[0]) / (d2 - d1)
    if max(abs(slope)) > 2.0 * laser.offset_max_mm / (d2 - d1):
        return Expected(tuple(edges), "tilt", tuple(centres))
    axis = np.array([slope[0], slope[1], 1.0]) / math.sqrt(1.0 + slope @ slope)
    below = np.array([-centres[0][0], -centres[0][1], -d1])  # the guessed tip there: the axis through S's origin
    top = below + axis * (d1 + laser.clearance_mm) / axis[2]
    bottom = below + axis * (d1 - laser.clearance_mm) / axis[2]
    span = float(np.linalg.norm(top - bottom))
    if geo.on("x", top, False):
        return Expected(tuple(edges), "no_tip", tuple(centres), axis)
    down = [e for e in geo.edges_along("x", lambda s: top + (bottom - top) * s / span, span) if e[2]]
    if not down:
        return Expected(tuple(edges), "no_tip", tuple(centres), axis)
    hit_down = down[0][1]
    up = [e for e in geo.edges_along("x", lambda s: bottom + (top - bottom) * s / span, span) if not e[2]]
    hit_up = up[0][1] if up else None
    if hit_up is None:
        return Expected(tuple(edges), "no_tip", tuple(centres), axis)
    tcp = tcp_from(cell, centres, axis, (hit_down, hit_up))
    halt = "too_far" if np.linalg.norm(tcp - geo.guess[:3, 3]) > laser.offset_max_mm else None
    return Expected(tuple(edges), halt, tuple(centres), axis, (hit_down, hit_up), tcp)
