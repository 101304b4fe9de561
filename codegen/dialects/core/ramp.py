"""A move's time in the interpreter's clock: distance over speed, with ramps a trapezoid (or a triangle) of speed."""

from __future__ import annotations

import math

import numpy as np

UNKNOWN_TRAVEL_S = 1.0  # assumed duration of a move whose start or end pose the clock does not know


def ramp_seconds(distance_mm: float, speed_mm_s: float, accel_mm_s2: float | None) -> float:
    """A straight move of distance_mm from standstill to standstill at speed_mm_s with accel_mm_s2 up and down
    (None or 0: no ramp, distance over speed): d / v + v / a where the move reaches v (d >= v^2 / a), else the
    triangle 2 sqrt(d / a)."""
    if not accel_mm_s2 or accel_mm_s2 <= 0:
        return distance_mm / speed_mm_s
    if distance_mm >= speed_mm_s**2 / accel_mm_s2:
        return distance_mm / speed_mm_s + speed_mm_s / accel_mm_s2
    return 2.0 * math.sqrt(distance_mm / accel_mm_s2)


def ramp_time_at(s_mm: float, distance_mm: float, speed_mm_s: float, accel_mm_s2: float | None) -> float:
    """When a move as ramp_seconds times it has covered s_mm of its distance_mm (s from its start)."""
    if not accel_mm_s2 or accel_mm_s2 <= 0:
        return s_mm / speed_mm_s
    peak = min(speed_mm_s, math.sqrt(max(0.0, distance_mm) * accel_mm_s2))  # a triangle peaks below the speed
    ramp = peak * peak / (2.0 * accel_mm_s2)  # the distance of each ramp
    total = ramp_seconds(distance_mm, speed_mm_s, accel_mm_s2)
    s = min(max(s_mm, 0.0), distance_mm)
    if s <= ramp:
        return math.sqrt(2.0 * s / accel_mm_s2)
    if s <= distance_mm - ramp:
        return peak / accel_mm_s2 + (s - ramp) / peak
    return total - math.sqrt(2.0 * (distance_mm - s) / accel_mm_s2)


def ramp_distance_at(t: float, distance_mm: float, speed_mm_s: float, accel_mm_s2: float | None) -> float:
    """How far a move as ramp_seconds times it has come t s after its start (mm, the inverse of ramp_time_at)."""
    total = ramp_seconds(distance_mm, speed_mm_s, accel_mm_s2)
    if t <= 0.0:
        return 0.0
    if t >= total:
        return distance_mm
    if not accel_mm_s2 or accel_mm_s2 <= 0:
        return t * speed_mm_s
    peak = min(speed_mm_s, math.sqrt(max(0.0, distance_mm) * accel_mm_s2))
    up = peak / accel_mm_s2
    if t <= up:
        return 0.5 * accel_mm_s2 * t * t
    if t <= total - up:
        return 0.5 * peak * up + peak * (t - up)
    left = total - t
    return distance_mm - 0.5 * accel_mm_s2 * left * left


def travel_seconds(
    start: np.ndarray | None, end: np.ndarray | None, speed_mm_s: float | None, accel_mm_s2: float | None = None
) -> float:
    """How long a move takes in the interpreter's clock: the TCP's straight-line distance over the
    programmed TCP speed (a pure rotation takes none); with a path acceleration (a dialect that knows the
    one in force), from standstill to standstill: a trapezoid, or a triangle where the move is too short to
    reach the speed (ramp_seconds). A move whose start or end pose is not known while the program runs (the
    first move, from wherever the arm stands; a joint target, whose pose comes from the arm's kinematics when
    the run ends) takes UNKNOWN_TRAVEL_S. Enough to order waits, timeouts and a photo against the motion."""
    if not speed_mm_s or speed_mm_s <= 0:
        return 0.0
    if start is None or end is None:
        return UNKNOWN_TRAVEL_S
    d = end[:3, 3] - start[:3, 3]
    return ramp_seconds(math.sqrt(d.dot(d)), speed_mm_s, accel_mm_s2)  # np.linalg.norm's own sum, without its call
