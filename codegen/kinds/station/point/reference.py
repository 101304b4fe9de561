"""Point correction's float64 reference (source 000): the mark now, the correction D, every corrected pose."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from codegen.exactcache import exact_cache
from codegen.guard import (
    INVALID_READING,
    ROTATION_OVER_LIMIT,
    SHIFT_OVER_LIMIT,
    UNKNOWN_STATION,
    reading_in_range,
)
from codegen.kinds.station.section import section_of
from codegen.poses import concat, invert, matrix_from_rotation_translation, rotz, wrap_deg
from codegen.reference import ExpectedTrace, path_moves

NAME = "point"  # the mode's name: a station's `mode`


@dataclass(frozen=True)
class PointSpec:
    """The mark at calibration: x mm, y mm, theta deg in the robot base frame; the poses the reading does not move."""

    mark: tuple[float, float, float]
    fixed: frozenset[str] = frozenset()


@dataclass(frozen=True)
class Reading:
    """What the camera reports: station id (barcode) and the mark in the base frame, mm and deg."""

    station_id: int
    x: float
    y: float
    theta: float


@dataclass(frozen=True)
class PointDetail:
    shift_mm: float
    rotation_deg: float  # wrap(tn_theta - t_theta), before the camera sign
    phi_deg: float | None = None  # applied rotation, angle_sign * rotation_deg
    correction: np.ndarray | None = None  # D


def mark2base(x: float, y: float, theta_deg: float) -> np.ndarray:
    return matrix_from_rotation_translation(rotz(math.radians(theta_deg)), (x, y, 0.0))


@exact_cache(maxsize=4096)
def base2mark(x: float, y: float, theta_deg: float) -> np.ndarray:
    """Inverse of mark2base (a station's calibration mark: computed once, read-only)."""
    out = invert(mark2base(x, y, theta_deg))
    out.flags.writeable = False
    return out


def expected_trace(cell, reading: Reading, enforce_limits: bool = True) -> ExpectedTrace:
    """The trace a correct program produces; enforce_limits=False computes the moves regardless."""
    section = section_of(cell)
    station = section.station_by_id(reading.station_id)
    if station is None:
        return ExpectedTrace("halt", UNKNOWN_STATION)
    if station.mode != NAME:
        raise ValueError(f"station {station.name} is a {station.mode} station, not a point station")
    if not reading_in_range(reading.x, reading.y, reading.theta):
        return ExpectedTrace("halt", INVALID_READING, station)
    tx, ty, t_theta = station.spec.mark
    shift = math.hypot(reading.x - tx, reading.y - ty)
    rotation = wrap_deg(reading.theta - t_theta)
    # Compared squared, as the programs do (no square root on the controller).
    if enforce_limits and (reading.x - tx) ** 2 + (reading.y - ty) ** 2 > section.limits.max_shift_mm**2:
        return ExpectedTrace("halt", SHIFT_OVER_LIMIT, station, detail=PointDetail(shift, rotation))
    if enforce_limits and abs(rotation) > section.limits.max_rotation_deg:
        return ExpectedTrace("halt", ROTATION_OVER_LIMIT, station, detail=PointDetail(shift, rotation))

    phi = section.angle_sign * rotation
    # The part moved rigidly with the mark: partnow2base = marknow2base . base2markcal . part2base
    marknow2base = mark2base(reading.x, reading.y, t_theta + phi)
    correction = concat(base2mark(tx, ty, t_theta), marknow2base)  # D: a taught pose P becomes D . P
    moves = path_moves(cell, station, correction, station.spec.fixed)
    work, work_new = station.poses[-1].matrix(), moves[len(station.poses) - 1].tcp2base
    deviation = (
        float(station.id),
        float(work_new[0, 3] - work[0, 3]),
        float(work_new[1, 3] - work[1, 3]),
        reading.x - tx,
        reading.y - ty,
        phi,
    )
    return ExpectedTrace("ok", None, station, tuple(moves), deviation, PointDetail(shift, rotation, phi, correction))
