"""Independent float64 reference: guard outcome and corrected poses from 4x4 matrix products."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np

from codegen.cell import READING_RANGE_DEG, READING_RANGE_MM, Cell, Station
from codegen.poses import concat, invert, matrix_from_rotation_translation, rotz, wrap_deg

# Halt reasons, in the order the guard checks them.
UNKNOWN_STATION = "unknown_station"
INVALID_READING = "invalid_reading"
SHIFT_OVER_LIMIT = "shift_over_limit"
ROTATION_OVER_LIMIT = "rotation_over_limit"
NOT_CONVERGED = "not_converged"
HALT_REASONS = (UNKNOWN_STATION, INVALID_READING, SHIFT_OVER_LIMIT, ROTATION_OVER_LIMIT, NOT_CONVERGED)
PIXEL_RANGE = 1_000_000.0  # a camera reading beyond this many pixels is treated as invalid

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
    deviation: tuple[float, ...] | None = None  # point: station id, dx1, dy1, dx2, dy2, dtheta
    # frame mode: station id, dx, dy, alpha, photos
    iterations: int | None = None  # frame mode: photos taken
    final_residual: tuple[float, float] | None = None  # frame mode: |res| mm, |gamma| deg of the last photo
    residuals: tuple[tuple[float, float], ...] = ()  # frame mode: every photo's residual


def reading_is_valid(reading: Reading) -> bool:
    """Finite and inside the plausible range; NaN fails every comparison, as on a controller."""
    return (
        abs(reading.x) <= READING_RANGE_MM
        and abs(reading.y) <= READING_RANGE_MM
        and abs(reading.theta) <= READING_RANGE_DEG
    )


def base2mark(x: float, y: float, theta_deg: float) -> np.ndarray:
    return matrix_from_rotation_translation(rotz(math.radians(theta_deg)), (x, y, 0.0))


@lru_cache(maxsize=4096)
def mark2base(x: float, y: float, theta_deg: float) -> np.ndarray:
    """Inverse of base2mark (a station's calibration mark: computed once, read-only)."""
    out = invert(base2mark(x, y, theta_deg))
    out.flags.writeable = False
    return out


def expected_trace(cell: Cell, reading: Reading, enforce_limits: bool = True) -> Trace:
    """The trace a correct program produces; enforce_limits=False computes the moves regardless."""
    station = cell.station_by_id(reading.station_id)
    if station is None:
        return Trace("halt", UNKNOWN_STATION)
    if station.mode == "frame":
        raise ValueError(f"station {station.name} is in frame mode: use expected_frame_trace")
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
    base2mark_now = base2mark(reading.x, reading.y, t_theta + phi)
    correction = concat(base2mark_now, mark2base(tx, ty, t_theta))
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


@dataclass(frozen=True)
class FrameCase:
    """Where the frame-mode station's mark really is, relative to its calibration frame, and the camera."""

    station_id: int
    dx: float  # mm, in the calibration frame's axes
    dy: float
    alpha: float  # deg
    camera: object  # codegen.camera.CameraModel


def expected_frame_trace(cell: Cell, case: FrameCase, nudge: float = 0.0) -> Trace:
    """Source 001's loop in float64 against the simulated camera, with the update proven in
    derivation.frame_update. nudge scales the tolerances by (1 + nudge): a float32 controller may
    decide the other way when a residual sits on the tolerance."""
    from codegen.camera import SimulatedCamera

    station = cell.station_by_id(case.station_id)
    if station is None:
        return Trace("halt", UNKNOWN_STATION)
    base2frame0, frame2photo = station.frame.matrix(), station.photo.matrix()
    base2mark = concat(base2frame0, frame_offset(case.dx, case.dy, case.alpha))
    camera = SimulatedCamera(case.camera, cell.handeye, cell.angle_sign, base2frame0, frame2photo, base2mark)
    handeye = np.array(cell.handeye)
    refine, limits = cell.refine, cell.limits
    tol_mm, tol_deg = refine.tolerance_mm * (1 + nudge), refine.tolerance_deg * (1 + nudge)
    dx = dy = alpha = 0.0
    moves: list[Move] = []
    photos, converged, residual = 0, False, None
    residuals: list[tuple[float, float]] = []
    while photos < refine.max_iterations:
        base2tcp = concat(base2frame0, frame_offset(dx, dy, alpha), frame2photo)
        moves.append(Move(JOINT, "photo", base2tcp))
        photos += 1
        u, v, angle = camera.photo(base2tcp)
        if not (abs(u) <= PIXEL_RANGE and abs(v) <= PIXEL_RANGE and abs(angle) <= READING_RANGE_DEG):
            return Trace(
                "halt", INVALID_READING, station, moves=tuple(moves), iterations=photos, residuals=tuple(residuals)
            )
        res_x, res_y = handeye @ np.array([u, v, 1.0])
        gamma = cell.angle_sign * angle
        residual = (math.hypot(res_x, res_y), abs(gamma))
        residuals.append(residual)
        if res_x**2 + res_y**2 < tol_mm**2 and abs(gamma) < tol_deg:
            converged = True
            break
        c, s_ = math.cos(math.radians(alpha)), math.sin(math.radians(alpha))
        dx, dy, alpha = dx + c * res_x - s_ * res_y, dy + s_ * res_x + c * res_y, alpha + gamma
        if dx**2 + dy**2 > limits.max_shift_mm**2:
            return Trace(
                "halt", SHIFT_OVER_LIMIT, station, moves=tuple(moves), iterations=photos, residuals=tuple(residuals)
            )
        if abs(alpha) > limits.max_rotation_deg:
            return Trace(
                "halt", ROTATION_OVER_LIMIT, station, moves=tuple(moves), iterations=photos, residuals=tuple(residuals)
            )
    if not converged:
        return Trace(
            "halt",
            NOT_CONVERGED,
            station,
            moves=tuple(moves),
            iterations=photos,
            final_residual=residual,
            residuals=tuple(residuals),
        )
    base2frame = concat(base2frame0, frame_offset(dx, dy, alpha))
    for i, pose in enumerate(station.poses):
        moves.append(Move(JOINT if i == 0 else LINEAR, pose.name, concat(base2frame, pose.matrix())))
    return Trace(
        "ok",
        None,
        station,
        moves=tuple(moves),
        deviation=(float(station.id), dx, dy, alpha, float(photos)),
        iterations=photos,
        final_residual=residual,
        base2base_new=base2frame,
        residuals=tuple(residuals),
    )


def frame_offset(dx: float, dy: float, alpha_deg: float) -> np.ndarray:
    """Trans(dx, dy, 0) . Rz(alpha): a frame moved in its own x-y plane."""
    return matrix_from_rotation_translation(rotz(math.radians(alpha_deg)), (dx, dy, 0.0))


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
    if trace.reason == NOT_CONVERGED:
        return f"station {name}: frame not converged after {cell.refine.max_iterations} photos"
    raise ValueError(f"not a halt: {trace.status}")
