"""Independent float64 reference: guard outcome and corrected poses from 4x4 matrix products."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from codegen.cell import READING_RANGE_DEG, READING_RANGE_MM, Cell, Station
from codegen.poses import concat, invert, matrix_from_rotation_translation, rotz

# Halt reasons, in the order the guard checks them.
UNKNOWN_STATION = "unknown_station"
INVALID_READING = "invalid_reading"
SHIFT_OVER_LIMIT = "shift_over_limit"
ROTATION_OVER_LIMIT = "rotation_over_limit"
HALT_REASONS = (UNKNOWN_STATION, INVALID_READING, SHIFT_OVER_LIMIT, ROTATION_OVER_LIMIT)

JOINT = "joint"
LINEAR = "linear"


@dataclass(frozen=True)
class Reading:
    """What the camera reports: station id (barcode) and the mark in the base frame, mm and deg."""

    station_id: int
    x: float
    y: float
    theta: float


@dataclass(frozen=True)
class Move:
    kind: str  # JOINT or LINEAR
    pose_name: str
    base2tcp: np.ndarray = field(compare=False)


@dataclass(frozen=True)
class Trace:
    """Expected behaviour of a correct program for one reading."""

    status: str  # "ok" or "halt"
    reason: str | None = None
    station: Station | None = None
    shift_mm: float | None = None
    rotation_deg: float | None = None  # wrap(tn_theta - t_theta), before the camera sign
    phi_deg: float | None = None  # applied rotation, angle_sign * rotation_deg
    base2base_new: np.ndarray | None = field(default=None, compare=False)  # D
    moves: tuple[Move, ...] = ()
    deviation: tuple[float, ...] | None = None  # station id, dx1, dy1, dx2, dy2, dtheta


def wrap_deg(angle: float) -> float:
    """Angle in degrees into (-180, 180]."""
    out = math.remainder(angle, 360.0)
    return 180.0 if out == -180.0 else out


def reading_is_valid(reading: Reading) -> bool:
    """Finite and inside the plausible range; NaN fails every comparison, as on a controller."""
    return (
        abs(reading.x) <= READING_RANGE_MM
        and abs(reading.y) <= READING_RANGE_MM
        and abs(reading.theta) <= READING_RANGE_DEG
    )


def base2mark(x: float, y: float, theta_deg: float) -> np.ndarray:
    return matrix_from_rotation_translation(rotz(math.radians(theta_deg)), (x, y, 0.0))


def expected_trace(cell: Cell, reading: Reading, enforce_limits: bool = True) -> Trace:
    """The trace a correct program produces; enforce_limits=False computes the moves regardless."""
    station = cell.station_by_id(reading.station_id)
    if station is None:
        return Trace("halt", UNKNOWN_STATION)
    if not reading_is_valid(reading):
        return Trace("halt", INVALID_READING, station)
    tx, ty, t_theta = station.mark
    shift = math.hypot(reading.x - tx, reading.y - ty)
    rotation = wrap_deg(reading.theta - t_theta)
    # Compared squared, as the programs do (no square root on the controller).
    if enforce_limits and (reading.x - tx) ** 2 + (reading.y - ty) ** 2 > cell.limits.max_shift_mm**2:
        return Trace("halt", SHIFT_OVER_LIMIT, station, shift, rotation)
    if enforce_limits and abs(rotation) > cell.limits.max_rotation_deg:
        return Trace("halt", ROTATION_OVER_LIMIT, station, shift, rotation)

    phi = cell.angle_sign * rotation
    # The part moved rigidly with the mark: base2part_now = base2mark_now . mark2base_cal . base2part
    base2mark_cal = base2mark(tx, ty, t_theta)
    base2mark_now = base2mark(reading.x, reading.y, t_theta + phi)
    correction = concat(base2mark_now, invert(base2mark_cal))
    moves = []
    for i, pose in enumerate(station.poses):
        base2tcp = concat(correction, pose.matrix())
        moves.append(Move(JOINT if i == 0 else LINEAR, pose.name, base2tcp))
    work, work_new = station.poses[-1].matrix(), moves[-1].base2tcp
    deviation = (
        float(station.id),
        float(work_new[0, 3] - work[0, 3]),
        float(work_new[1, 3] - work[1, 3]),
        reading.x - tx,
        reading.y - ty,
        phi,
    )
    return Trace("ok", None, station, shift, rotation, phi, correction, tuple(moves), deviation)


def halt_message(cell: Cell, trace: Trace, station_id: int) -> str:
    """The operator message every generated program shows when it halts (a contract)."""
    limits = cell.limits
    if trace.reason == UNKNOWN_STATION:
        return f"unknown station id {station_id}"
    name = trace.station.name if trace.station else "?"
    if trace.reason == INVALID_READING:
        return f"station {name}: invalid mark reading"
    if trace.reason == SHIFT_OVER_LIMIT:
        return f"station {name}: mark shift over {limits.max_shift_mm:g} mm, recalibrate"
    if trace.reason == ROTATION_OVER_LIMIT:
        return f"station {name}: mark rotation over {limits.max_rotation_deg:g} deg, recalibrate"
    raise ValueError(f"not a halt: {trace.status}")
