"""The stations' arm poses, and each over the correction region: the joints the controller takes, and whether the taught
configuration can be named in the program (its turn and quadrant fields hold over the whole region)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from codegen.controllers import get_target
from codegen.exactcache import exact_cache
from codegen.kinds.station.mode import mode_of
from codegen.kinds.station.section import section_of
from codegen.robot import solve
from codegen.robot.config import FORMS, named_in_full, nearest_margin
from codegen.robot.taught import JOINTS_MATCH_DEG, ArmPose, ReachError, configuration, select

MIN_DIRECTIONS = 16  # directions on each ring of the shift disc, at least
RING_SPACING_MM = 5.0  # and at most this far apart on the boundary
INNER_RINGS = (0.5,)  # fractions of the shift limit sampled inside the disc (and the centre)
MIN_ROTATIONS = 9  # rotations from -limit to +limit (both ends included), at least
ROTATION_SPACING_DEG = 2.5  # and at most this far apart


@dataclass(frozen=True)
class StationRegion:
    taught: list[ArmPose]
    offsets: np.ndarray  # (N, 3) readings: dx, dy mm, rotation deg (row 0: nothing moved)
    grid: tuple[int, int]  # rotations, directions: rows 1.. are rotations x (centre + rings x directions)
    joints: np.ndarray  # (N, M, 6) deg, NaN where the controller finds no solution
    branch: np.ndarray  # (N, M) the analytic solution taken (-1: none)
    named: tuple[bool, ...]  # per arm pose: the program names its full configuration (robconf, S and T)


def sampling(max_shift_mm: float, max_rotation_deg: float) -> tuple[int, int]:
    """How many rotations and ring directions sample the region finely enough."""
    rotations = max(MIN_ROTATIONS, math.ceil(2 * max_rotation_deg / ROTATION_SPACING_DEG) + 1)
    directions = max(MIN_DIRECTIONS, math.ceil(2 * math.pi * max_shift_mm / RING_SPACING_MM))
    return rotations, directions


@exact_cache(maxsize=16)
def offsets(max_shift_mm: float, max_rotation_deg: float) -> np.ndarray:
    """(dx, dy, rotation) over the guard's region: no change first, then the shift disc's boundary,
    an inner ring and the centre, each at rotations from -limit to +limit (corners included)."""
    rotation_count, directions = sampling(max_shift_mm, max_rotation_deg)
    angles = np.linspace(0.0, 2 * math.pi, directions, endpoint=False)
    shifts = [np.zeros((1, 2))]
    for fraction in (*INNER_RINGS, 1.0):
        r = fraction * max_shift_mm
        shifts.append(np.column_stack([r * np.cos(angles), r * np.sin(angles)]))
    disc = np.concatenate(shifts)
    rotations = np.linspace(-max_rotation_deg, max_rotation_deg, rotation_count)
    grid = np.column_stack([np.tile(disc, (len(rotations), 1)), np.repeat(rotations, len(disc))])
    out = np.concatenate([np.zeros((1, 3)), grid])
    out.flags.writeable = False
    return out


def station_region(cell, target: str, station) -> StationRegion:
    """The station's arm poses over the correction region on the target's arm, in the configuration the cell hands
    down for it (worked out once per cell and target by the kind's plan, codegen/kinds/station/plan.py); ReachError
    where a taught pose has no solution."""
    robot = cell.robot
    arm = robot.arms[target]
    form = get_target(target).configuration
    taught = arm_poses(cell, target, station)
    region_offsets = offsets(*_bounds(cell))
    region = mode_of(station).region(cell, station, region_offsets)  # (N, M, 4, 4)
    solutions = solve.branches(arm, solve.flange_poses(region, robot.tool.tcp2flange))  # (N, M, 8, 6)
    home = np.broadcast_to(np.asarray(robot.home[target], dtype=float), (len(region_offsets), 6))
    joints, branches, named = [], [], []
    previous = home
    for m, pose in enumerate(taught):
        q, b, full = move_joints(arm, form, pose, solutions[:, m], previous)
        if (
            pose.motion == "joint"
            and not full
            and form != "joints"
            and not _one_way(arm, form, pose, solutions[:, m], previous)
        ):
            # the controller's nearest solution would turn an axis one way for some readings and the other way
            # for others: the program names the full configuration after all where it takes every reading (at
            # a boundary: the boundary's own value, codegen/robot/config.py), else the cell must change
            q, b = select(form, arm, solutions[:, m], configuration(form, arm, pose.joints))
            if np.isnan(q).any():
                raise ReachError(_two_ways(cell, target, station, pose))
            full = True
        joints.append(q)
        branches.append(b)
        named.append(full)
        previous = np.where(np.isnan(q), previous, q)
    grid = sampling(*_bounds(cell))
    return StationRegion(
        taught, region_offsets, grid, np.stack(joints, axis=1), np.stack(branches, axis=1), tuple(named)
    )


def move_joints(arm, form: str, pose: ArmPose, solutions: np.ndarray, previous: np.ndarray, named=None):
    """The joints the controller takes for one arm pose over a batch of corrected poses, and whether the
    program names the full configuration. A joint move names it when every corrected pose can be
    taken in it (the controller then goes there); otherwise the program names only what holds (the
    status bits without the turn: the shortest turn; or the configuration check off: the closest
    configuration) and the arm goes to the solution nearest where it stands. The "joints" form names
    joints (the inverse kinematics nearest the taught joints); a linear move continues from the joints
    before it. Where the controller checks a linear move's end configuration (the "confdata" form), the
    program names it only where it holds. named: what the program names (verify's cases), None:
    decide it from these poses (the region)."""
    if form == "joints":
        if pose.motion == "joint":
            q, b = solve.nearest(arm, solutions, np.broadcast_to(pose.joints, previous.shape))
        else:
            q, b = solve.nearest(arm, solutions, previous)
        return q, b, True
    value = configuration(form, arm, pose.joints)
    if pose.motion == "joint" and named is not False:
        q, b = select(form, arm, solutions, value)
        if named or (not np.isnan(q).any() and _holds(form, arm, q, pose)):
            return q, b, True
    q, b = solve.nearest(arm, solutions, previous)
    if named is not None:
        return q, b, named
    full = pose.motion == "linear" and form != "confdata"  # LIN ignores S and T: naming them is harmless
    if form == "confdata" and pose.motion == "linear":
        found = ~np.isnan(q).any(axis=-1)
        full = bool(np.all(FORMS[form].many(arm, q[found]) == np.asarray(value))) and _holds(form, arm, q[found], pose)
    return q, b, full


# Over the sampled region a tie's margin (how much nearer the nearest solution is than the next) changes by at most
# about twice the change of the reading's rotation: samples this far from a tie cannot have one between them.
REGION_TIE_DEG = 2.0 * ROTATION_SPACING_DEG


def _one_way(arm, form: str, pose: ArmPose, solutions: np.ndarray, previous: np.ndarray) -> bool:
    """A joint move the program names only partly (the controller's nearest solution) has one nearest solution
    at every reading of the region (none half a turn of an axis from the pose before it, nor two branches as
    near): it turns each axis the same way whatever the reading."""
    value = configuration(form, arm, pose.joints)
    for sols, before in zip(solutions, previous, strict=True):
        if nearest_margin(arm, FORMS[form].candidates(arm, sols, value), before)[0] < REGION_TIE_DEG:
            return False
    return True


def _two_ways(cell, target: str, station, pose: ArmPose) -> str:
    arm = cell.robot.arms[target]
    return (
        f"station {station.id} {station.name!r} pose {pose.name!r} ({target}, {arm.model}): from the pose before it "
        "an axis is about half a turn away for some readings: the controller would turn it one way for some "
        "readings and the other way for others, and no configuration the program could name takes every reading; "
        "give [cell.robot.home] another axis value, or teach the pose turned"
    )


def _holds(form: str, arm, q: np.ndarray, pose: ArmPose) -> bool:
    """The configuration at every corrected pose's joints is decided away from its boundaries (not by rounding:
    codegen/robot/config.py named_in_full); ReachError at a singular pose."""
    try:
        return named_in_full(form, arm, q)
    except ValueError as exc:
        raise ReachError(f"pose {pose.name!r} ({arm.model}): {exc}") from None


def arm_poses(cell, target: str, station) -> list[ArmPose]:
    """The station's arm poses with their taught joints, in the order the program visits them."""
    robot = cell.robot
    arm, home = robot.arms[target], np.asarray(robot.home[target], dtype=float)
    # the configuration handed down with the cell: the cell's own or the posture chosen for it
    # (codegen/kinds/station/posture.py postured)
    given = section_of(cell).station_by_id(station.id).config.get(target) or {}
    poses = mode_of(station).arm_poses(cell, station)
    flange2base = solve.flange_poses(np.array([p[1] for p in poses]), robot.tool.tcp2flange)
    solutions = solve.branches(arm, flange2base)
    out: list[ArmPose] = []
    previous = home
    for (name, tcp2base, motion), sols, flange in zip(poses, solutions, flange2base, strict=True):
        where = f"station {station.id} {station.name!r} pose {name!r} ({target}, {arm.model})"
        if np.isnan(sols).all():
            raise ReachError(f"{where}: out of reach: {solve.unreachable_text(arm, flange)}")
        config = given.get(name)
        if config is None:
            joints, branch = solve.nearest(arm, sols, previous if motion == "linear" else home)
            if np.isnan(joints).any():
                raise ReachError(f"{where}: no solution within the joint limits")
        elif config.form == "joints":
            joints, branch = solve.nearest(arm, sols, np.asarray(config.value))
            if np.isnan(joints).any() or np.max(np.abs(joints - config.value)) > JOINTS_MATCH_DEG:
                raise ReachError(
                    f"{where}: the taught joints {list(config.value)} do not reach this pose "
                    f"(nearest solution {np.round(joints, 2).tolist()})"
                )
        else:
            joints, branch = select(config.form, arm, sols, config.value)
            if np.isnan(joints).any():
                raise ReachError(f"{where}: the arm cannot take this pose in configuration {config.value}")
        joints = np.where(np.abs(joints) < solve.BOUNDARY_DEG, 0.0, joints)  # an axis at 0 is not negative
        out.append(ArmPose(name, motion, tcp2base, joints, int(branch)))
        previous = joints
    return out


def _bounds(cell) -> tuple[float, float]:
    """The readings' limits of the cell's stations: the largest shift (mm) and rotation (deg)."""
    limits = section_of(cell).limits
    return limits.max_shift_mm, limits.max_rotation_deg
