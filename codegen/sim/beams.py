"""Two simulated displacement sensors with crossed beams and the pin they see (source 003's automatic TCP method)."""

# The sensor frame S: beam X runs along S's +x from its sensor at x = -reach, beam Y along +y from
# y = -reach; both lie in S's plane z = 0 and cross at its origin. A sensor reads the distance from
# itself to the first surface on its beam (None: nothing within its range), with Gaussian noise and
# rounded to its resolution. The tool is a pin: a cylinder of radius rho about the tool's axis, from
# the tip (a flat end square to the axis) up to `length`; the axis is the tool's z in the flange frame,
# which a bent tool has tilted. Nothing here knows the calibration's formulas: the readings come from
# ray-cylinder geometry only.

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np


@dataclass(frozen=True)
class Pin:
    """The tool as the sensors see it: tcp2flange (4x4, its z the pin's axis, pointing from the flange
    towards the tip: the pin runs from the tip back along -z), radius and length (mm)."""

    tcp2flange: np.ndarray
    radius: float
    length: float = 60.0

    def in_sensor(self, flange2sensor: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The tip and the unit axis pointing from the tip up the pin, in S."""
        tcp = flange2sensor @ self.tcp2flange
        return tcp[:3, 3], -tcp[:3, 2]


@dataclass
class Sensors:
    """The two sensors: reach (mm from each sensor to the crossing), range (what they read at most),
    noise (standard deviation, mm), resolution (mm), rng (numpy Generator)."""

    reach: float = 100.0
    range_mm: float = 200.0
    noise: float = 0.0
    resolution: float = 0.0
    rng: object = field(default_factory=lambda: np.random.default_rng(0))

    def _read(self, true: float | None) -> float | None:
        if true is None or true > self.range_mm:
            return None
        value = true + (self.rng.normal(0.0, self.noise) if self.noise > 0 else 0.0)
        if self.resolution > 0:
            value = round(value / self.resolution) * self.resolution
        return value

    def read(self, pin: Pin, flange2sensor: np.ndarray) -> tuple[float | None, float | None]:
        """(beam X, beam Y) readings with the flange there."""
        tip, axis = pin.in_sensor(flange2sensor)
        x = entry_along(tip, axis, pin.radius, pin.length, np.array([-self.reach, 0.0, 0.0]), np.array([1.0, 0, 0]))
        y = entry_along(tip, axis, pin.radius, pin.length, np.array([0.0, -self.reach, 0.0]), np.array([0, 1.0, 0]))
        return self._read(x), self._read(y)

    def blocked(self, pin: Pin, flange2sensor: np.ndarray) -> tuple[bool, bool]:
        """Whether each beam meets the pin (before noise: a beam is interrupted or it is not)."""
        tip, axis = pin.in_sensor(flange2sensor)
        return tuple(
            entry_along(tip, axis, pin.radius, pin.length, origin, direction) is not None
            for origin, direction in (
                (np.array([-self.reach, 0.0, 0.0]), np.array([1.0, 0, 0])),
                (np.array([0.0, -self.reach, 0.0]), np.array([0, 1.0, 0])),
            )
        )


def entry_along(tip, axis, radius: float, length: float, origin, direction) -> float | None:
    """The distance from origin along direction (unit) to where the ray enters the pin (a cylinder about
    tip + s axis, 0 <= s <= length, radius), None when it misses: the ray's points inside the infinite
    cylinder form an interval (a quadratic), those between the end planes another (linear in the ray's
    parameter); the entry is the start of their common part, if it lies ahead."""
    w = origin - tip
    d_perp = direction - np.dot(direction, axis) * axis
    w_perp = w - np.dot(w, axis) * axis
    a, b, c = np.dot(d_perp, d_perp), 2.0 * np.dot(d_perp, w_perp), np.dot(w_perp, w_perp) - radius**2
    if a < 1e-15:  # the ray runs along the axis
        if c > 0:
            return None
        low, high = -math.inf, math.inf
    else:
        disc = b * b - 4 * a * c
        if disc < 0:
            return None
        root = math.sqrt(disc)
        low, high = (-b - root) / (2 * a), (-b + root) / (2 * a)
    # the end planes: 0 <= (w + t direction) . axis <= length
    along, start = float(np.dot(direction, axis)), float(np.dot(w, axis))
    if abs(along) < 1e-15:
        if not 0.0 <= start <= length:
            return None
    else:
        t0, t1 = (0.0 - start) / along, (length - start) / along
        low, high = max(low, min(t0, t1)), min(high, max(t0, t1))
    if low > high or high < 0:
        return None
    return max(low, 0.0)
