"""Vendor arm configurations (ABB confdata, KUKA Status/Turn) and the controllers' rules choosing a solution by them."""

# ABB: "Technical reference manual - RAPID Instructions, Functions and Data types" (RobotWare 6), data type
# confdata, "Robot configuration data for 6 axes serial robots" (older issues: RAPID Reference Manual, Data
# types, confdata, and "Basic Characteristics RAPID", 4 Robot Configuration, p. 6-32 ff.); the cfx table as
# quoted from that manual's page (developercenter.robotstudio.com .../RapidIFDTechRefManual/doc439.html):
#   cf1, cf4, cf6: the quadrant of axis 1, 4, 6: quadrant 0 is 0..90 deg in the positive direction from the
#     zero position, quadrant 1 is 90..180, quadrant -1 is 0..-90, and so on: floor(angle / 90).
#   cfx, "Robot configuration data for 6 axes serial robots", one of eight numbered by the table
#     cfx | wrist centre relative to axis 1 | wrist centre relative to lower arm | axis 5 angle
#      0  | in front of | in front of | positive        4 | behind | in front of | positive
#      1  | in front of | in front of | negative        5 | behind | in front of | negative
#      2  | in front of | behind      | positive        6 | behind | behind      | positive
#      3  | in front of | behind      | negative        7 | behind | behind      | negative
#   i.e. cfx = 4 a + 2 b + c. The boundary values (on axis 1, on the lower arm's line, axis 5 = 0) are counted
#   as "in front of" / "positive" here (the manual leaves them to the singularity).
# KUKA: "KUKA System Software 8.x, Operating and Programming Instructions for System Integrators" (KSS 8.3 SI
# V4, 2015), motion programming, sections "Status" and "Turn" (the same bits in the KSS 5.x Expert Programming
# manual). Read here through its quotations: the robot-forum.com threads "x_value of wrist root point" (the
# basic/overhead text) and "KUKA status bit flip/no-flip", and Siemens' SINUMERIK programming manual
# 6FC5398-2EP40-0BA0 (12/2019), 3.9 Transformations, STAT and TU, which defines the same bits for such arms:
#   Status bit 0: 0 basic area, 1 overhead area: the wrist point's x in the A1 coordinate system (= $ROBROOT
#     turned with axis 1) positive / negative;
#   Status bit 1: 0 for A3 < phi, 1 for A3 >= phi, phi the A3 angle at which the arm is stretched (0 when the
#     axes 3 and 4 intersect, otherwise set by their offset: here the angle where the wrist centre lines up
#     with axes 2 and 3);
#   Status bit 2: 0 for 0 <= A5 < 180 or A5 < -180, 1 for -180 <= A5 < 0 or A5 >= 180;
#   Turn bit i (i = 0..5): 1 when axis i+1 < 0 deg, 0 when >= 0.
# UR: get_inverse_kin(x, qnear) returns "the solution closest to qnear" (URScript manual); UR's staff on the
# UR forum ("Get_inverse_kin closest solution criteria"): "the sum of squared error", so Euclidean in joints.
#
# At a boundary. A pose the cell plans exactly on a boundary (Q straight ahead of the arm: axis 1 at 0; a
# vertical tool: axis 4 at 0 and axis 6 at 180) comes out of the float64 inverse kinematics as 0 +- 1e-12 or
# 180 +- 1e-12: its sign is rounding, and so is the controller's, whose own arithmetic lands on either side.
# No manual states which side the controller then takes. So a generated program never names such a field
# (holding, named_in_full below: a field that changes when any axis moves by ROUNDING_MARGIN_DEG): a KUKA
# PTP then gives the Status without the Turn ("the Turn value that results in the shortest possible path"),
# an ABB joint move runs with the configuration check off ("the closest configuration"), each the manual's
# rule for a target without that field, and codegen plans the move by the same rule (Form.loose). For
# hand-written programs the interpreter still reads a field named at a boundary as the boundary's own
# value (at_boundary, within BOUNDARY_DEG): KUKA Turn bit i is 1 only for axis i+1 < 0 deg (Siemens' TU,
# the same bits: "bit = 0: 0 <= theta < 360"), so an axis at 0 has its bit 0; Status bit 2 is 0 for
# 0 <= A5 < 180; ABB's quadrant of 0 .. 90 deg is 0 (floor(angle / 90): 0 -> 0, 180 -> 2, -180 -> -2); cfx
# counts the boundaries as above; the configuration named for the boundary selects a value within the margin
# on its own side or the boundary itself. robot-forum.com reports (KSS 5.5) that a PTP disregards the Turn
# bit of an axis within about 2 deg of 0 and takes the shorter way; nothing here relies on it.

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from codegen.robot import solve
from codegen.robot.arms import Arm
from codegen.robot.kinematics import wrap_deg, wrap_deg_float
from codegen.robot.opw import OPW

BOUNDARY_MM = 1e-6  # a wrist centre this close to axis 1 is on it (mm)
BOUNDARY_SIN = math.radians(solve.BOUNDARY_DEG)  # the wrist centre this close to the lower arm's line: on it (sine)


def at_boundary(joints_deg) -> np.ndarray:
    """Axis values with each one within BOUNDARY_DEG of a multiple of 90 deg set to it (no negative zero): the
    boundaries of the quadrants, the signs and the status bits are multiples of 90."""
    q = np.asarray(joints_deg, dtype=float)
    nearest = 90.0 * np.round(q / 90.0)
    return np.where(np.abs(q - nearest) <= solve.BOUNDARY_DEG, nearest + 0.0, q)


def _at_boundary_one(q: list[float]) -> list[float]:
    """at_boundary of one pose's axis values as Python floats (the same operations)."""
    out = []
    for v in q:
        nearest = 90.0 * round(v / 90.0)
        out.append(nearest + 0.0 if abs(v - nearest) <= solve.BOUNDARY_DEG else v)
    return out


def _side(value, margin: float) -> np.ndarray:
    """A signed distance within the margin of 0 as 0."""
    return np.where(np.abs(value) <= margin, 0.0, value)


def _side_float(value: float, margin: float) -> float:
    """_side of one Python float."""
    return 0.0 if abs(value) <= margin else value


def abb_quadrant(joints_deg: np.ndarray) -> np.ndarray:
    """The confdata quadrant of an axis value: floor(angle / 90 deg) of the value at its boundary (at_boundary),
    integers of the input's shape."""
    return np.floor(at_boundary(joints_deg) / 90.0).astype(int)


def abb_confdata(kin: OPW, joints_deg: np.ndarray) -> np.ndarray:
    """(..., 6) axis values -> (..., 4) int (cf1, cf4, cf6, cfx) for an ABB 6-axis serial arm."""
    q = at_boundary(joints_deg)
    behind_axis1 = _side(kin.wrist_x_axis1(q), BOUNDARY_MM) < 0.0
    behind_lower_arm = _side(kin.elbow_side(q), BOUNDARY_SIN) < 0.0
    axis5_negative = q[..., 4] < 0.0
    cfx = 4 * behind_axis1.astype(int) + 2 * behind_lower_arm.astype(int) + axis5_negative.astype(int)
    return np.concatenate([abb_quadrant(q[..., [0, 3, 5]]), cfx[..., None]], axis=-1)


def _scalar_or_array(values: np.ndarray) -> int | np.ndarray:
    return int(values) if values.ndim == 0 else values


def _finite_one(joints_deg) -> list[float] | None:
    """One pose's axis values as Python floats; None for a batch or a value that is not finite (numpy then)."""
    q = np.asarray(joints_deg, dtype=float)
    if q.shape != (6,):
        return None
    values = q.tolist()
    return values if all(-math.inf < v < math.inf for v in values) else None


def _one_pose(solutions: np.ndarray, values) -> bool:
    """The one-pose path takes (8, 6) float64 solutions and integer configuration values; anything else (a
    batch, float32, a value given as a float) keeps numpy's own promotion rules: the batched path."""
    return (
        solutions.ndim == 2
        and solutions.dtype == np.float64
        and all(isinstance(v, int | np.integer) and not isinstance(v, bool) for v in values)
    )


def _kuka_status_one(kin: OPW, q: list[float]) -> int:
    q = _at_boundary_one(q)
    x, _ = kin.sides_one(q)
    a5 = q[4]
    a5_bit = (-180.0 <= a5 < 0.0) or a5 >= 180.0
    a3 = _side_float(wrap_deg_float(q[2] - kin.stretched_q3_deg), solve.BOUNDARY_DEG)
    return int(_side_float(x, BOUNDARY_MM) < 0.0) | int(a3 >= 0.0) << 1 | int(a5_bit) << 2


def _abb_cfx_one(kin: OPW, q: list[float]) -> int:
    q = _at_boundary_one(q)
    x, elbow = kin.sides_one(q)
    side, elbow = _side_float(x, BOUNDARY_MM), _side_float(elbow, BOUNDARY_SIN)
    return 4 * int(side < 0.0) + 2 * int(elbow < 0.0) + int(q[4] < 0.0)


def kuka_status(kin: OPW, joints_deg: np.ndarray) -> int | np.ndarray:
    """Status bits 0-2 of axis values (at their boundaries): an int for one (6,) pose, an int array (...) for a
    batch."""
    one = _finite_one(joints_deg)
    if one is not None:
        return _kuka_status_one(kin, one)
    q = at_boundary(joints_deg)
    overhead = _side(kin.wrist_x_axis1(q), BOUNDARY_MM) < 0.0
    a3_from_stretched = _side(wrap_deg(q[..., 2] - kin.stretched_q3_deg), solve.BOUNDARY_DEG)  # A3 - phi
    a3_at_or_above = a3_from_stretched >= 0.0
    a5 = q[..., 4]
    a5_bit = ((a5 >= -180.0) & (a5 < 0.0)) | (a5 >= 180.0)
    status = overhead.astype(int) | (a3_at_or_above.astype(int) << 1) | (a5_bit.astype(int) << 2)
    return _scalar_or_array(np.asarray(status))


def kuka_turn(joints_deg: np.ndarray) -> int | np.ndarray:
    """Turn: bit i set when axis i+1 < 0 deg (an axis at 0, its boundary, has its bit 0); an int for one (6,)
    pose, an int array (...) for a batch."""
    one = _finite_one(joints_deg)
    if one is not None:
        return sum(1 << axis for axis, value in enumerate(_at_boundary_one(one)) if value < 0.0)
    negative = at_boundary(joints_deg) < 0.0
    return _scalar_or_array(np.sum(negative.astype(int) << np.arange(6), axis=-1))


def by_confdata(arm: Arm, solutions: np.ndarray, conf) -> tuple[np.ndarray, np.ndarray]:
    """ABB (ConfJ/ConfL on): the solution whose robconf equals conf = (cf1, cf4, cf6, cfx): cf1, cf4 and
    cf6 name the quadrant of axes 1, 4 and 6 (hence their turn), cfx the branch."""
    cf1, cf4, cf6, cfx = conf
    if _one_pose(solutions, conf):
        return _first_one(arm, solutions, lambda row: _by_confdata_row(arm, row, conf))
    q = solutions.copy()
    for axis, quadrant in ((0, cf1), (3, cf4), (5, cf6)):  # the quadrant [90 k, 90 (k + 1)) at its boundaries
        q[..., axis] = solve.shift_into(q[..., axis], 90.0 * quadrant - solve.BOUNDARY_DEG)
    match = (abb_confdata(arm.kin, np.nan_to_num(q))[..., 3] == cfx) & solve.inside(arm, q) & ~np.isnan(q).any(axis=-1)
    for axis, quadrant in ((0, cf1), (3, cf4), (5, cf6)):
        match &= q[..., axis] < 90.0 * (quadrant + 1) - solve.BOUNDARY_DEG
    return solve.first(q, match)


def by_status_turn(arm: Arm, solutions: np.ndarray, status: int, turn: int) -> tuple[np.ndarray, np.ndarray]:
    """KUKA PTP to an E6POS with S and T: the branch whose Status bits 0-2 equal S's, each axis on the
    side of zero its Turn bit names (bit i set: axis i+1 < 0)."""
    if _one_pose(solutions, (status, turn)):
        return _first_one(arm, solutions, lambda row: _by_status_turn_row(arm, row, status, turn))
    q = solutions.copy()
    for axis in range(6):  # bit 1: the axis below 0 beyond its boundary; bit 0: at or above it
        negative = bool(turn >> axis & 1)
        if negative:
            q[..., axis] = np.where(q[..., axis] >= -solve.BOUNDARY_DEG, q[..., axis] - solve.TURN, q[..., axis])
        else:
            q[..., axis] = np.where(q[..., axis] < -solve.BOUNDARY_DEG, q[..., axis] + solve.TURN, q[..., axis])
    s = kuka_status(arm.kin, np.nan_to_num(q))
    match = ((s & 7) == (status & 7)) & solve.inside(arm, q) & ~np.isnan(q).any(axis=-1)
    return solve.first(q, match)


def _first_one(arm: Arm, solutions: np.ndarray, shifted) -> tuple[np.ndarray, np.ndarray]:
    """solve.first for one pose (8, 6) on Python floats: the first branch whose row, moved by shifted (None:
    no match), lies within the limits; as the batched path returns it (NaN joints and -1 when none)."""
    for index, row in enumerate(solutions.tolist()):
        if not all(-math.inf < v < math.inf for v in row):
            continue  # a branch without a solution
        q = shifted(row)
        if q is not None and solve.inside_float(q, arm.limits_deg):
            return np.array(q), np.array(index)
    return np.full(6, np.nan), np.array(-1)


def _by_confdata_row(arm: Arm, row: list[float], conf) -> list[float] | None:
    q = list(row)
    quadrants = ((0, conf[0]), (3, conf[1]), (5, conf[2]))
    for axis, quadrant in quadrants:
        q[axis] = solve.shift_into_float(q[axis], 90.0 * quadrant - solve.BOUNDARY_DEG)
    if _abb_cfx_one(arm.kin, q) != conf[3]:
        return None
    if not all(q[axis] < 90.0 * (quadrant + 1) - solve.BOUNDARY_DEG for axis, quadrant in quadrants):
        return None
    return q


def _by_status_turn_row(arm: Arm, row: list[float], status: int, turn: int) -> list[float] | None:
    q = [
        (v - solve.TURN if v >= -solve.BOUNDARY_DEG else v)
        if turn >> axis & 1
        else (v + solve.TURN if v < -solve.BOUNDARY_DEG else v)
        for axis, v in enumerate(row)
    ]
    return q if (_kuka_status_one(arm.kin, q) & 7) == (status & 7) else None


def with_status(arm: Arm, solutions: np.ndarray, status: int) -> np.ndarray:
    """The solutions whose KUKA Status bits 0-2 equal status's; the others NaN."""
    s = kuka_status(arm.kin, np.nan_to_num(solutions))
    return np.where(((s & 7) == (status & 7))[..., None], solutions, np.nan)


def abb_quadrants(q: np.ndarray) -> np.ndarray:
    """cf1, cf4, cf6 of axis values (..., 6) -> (..., 3)."""
    return abb_quadrant(np.asarray(q)[..., [0, 3, 5]])


@dataclass(frozen=True)
class Form:
    """How a controller's program names an arm configuration: `of` gives the program's value for joints,
    `select` the joints a move naming that value takes among the analytic solutions (q, branch), `many`
    the values of a batch of joints (..., 6) as an array (..., k). Where a field of the value depends on
    rounding (holding), the program names only `kept` (the fields that hold: their columns) and the move
    takes the solution nearest where the arm stands among `candidates` (the solutions the kept fields allow):
    the controller's own rule for a target without the rest (config.loose). A form of
    axis values (`exact`) names them as they are: no field of it is decided by a boundary."""

    of: Callable
    select: Callable
    many: Callable
    kept: tuple[int, ...]
    candidates: Callable
    exact: bool = False


FORMS = {  # a target's `configuration` fact -> its form
    # ABB without the configuration check (ConfJ \Off): "the robot moves to the specified position and
    # orientation with the closest configuration" (Basic Characteristics RAPID, Robot configuration)
    "confdata": Form(
        lambda arm, q: (*(int(v) for v in abb_quadrants(q)), int(abb_confdata(arm.kin, q)[3])),
        by_confdata,
        lambda arm, q: abb_confdata(arm.kin, q),
        (),
        lambda arm, solutions, value: solutions,
    ),
    # KUKA, a PTP with S and no T: the programmed Status, "the Turn value that results in the shortest
    # possible path" (KSS 8 manual, Status and Turn, as quoted in robot-forum.com thread 42877)
    "status_turn": Form(
        lambda arm, q: (int(kuka_status(arm.kin, q)), int(kuka_turn(q))),
        lambda arm, solutions, value: by_status_turn(arm, solutions, *value),
        lambda arm, q: np.stack([np.asarray(kuka_status(arm.kin, q)), np.asarray(kuka_turn(q))], axis=-1),
        (0,),
        lambda arm, solutions, value: with_status(arm, solutions, value[0]),
    ),
    "joints": Form(
        lambda arm, q: tuple(float(v) for v in q),
        lambda arm, solutions, value: solve.nearest(arm, solutions, np.asarray(value, dtype=float)),
        lambda arm, q: np.asarray(q, dtype=float),
        (0, 1, 2, 3, 4, 5),
        lambda arm, solutions, value: solutions,
        exact=True,
    ),
}

# A configuration field holds at joints when every axis moved by this much either way leaves it as it is.
# The controller computes a target's axes from the printed pose (4 decimals mm, 6 decimals deg) in its own
# arithmetic (KRL REAL and RAPID num are 32-bit floats: 6e-8 relative, 1e-5 deg on 180 deg, 1e-4 mm on
# 2 m), so its axis values lie within about 1e-4 deg of codegen's away from a singularity; 0.01 deg is a
# hundred times that. A field that does not hold (a vertical tool: axis 4 at 0, axis 6 at a multiple of
# 90; a target straight ahead: axis 1 at 0) depends on rounding: the program does not name it.
ROUNDING_MARGIN_DEG = 0.01
_NUDGES = np.concatenate([np.zeros((1, 6)), ROUNDING_MARGIN_DEG * np.eye(6), -ROUNDING_MARGIN_DEG * np.eye(6)])


def holding(form: str, arm: Arm, joints) -> np.ndarray:
    """Per field of the form's value (..., k), bool: the field is the same for the joints with any one axis
    moved by ROUNDING_MARGIN_DEG either way (it does not depend on rounding)."""
    q = np.asarray(joints, dtype=float)[..., None, :] + _NUDGES  # (..., 13, 6)
    values = np.asarray(FORMS[form].many(arm, q))
    if FORMS[form].exact:
        return np.ones(values.shape[:-2] + values.shape[-1:], dtype=bool)
    return np.all(values == values[..., :1, :], axis=-2)


def named_in_full(form: str, arm: Arm, joints) -> bool:
    """Every field of the configuration at all these joints (..., 6) holds: the program can name it whole.
    ValueError where even the fields a program names without the rest (Form.kept) do not hold: the arm is at
    a singularity there."""
    held = holding(form, arm, joints)
    held = held.reshape(-1, held.shape[-1])
    kept = list(FORMS[form].kept)
    if kept and not held[:, kept].all():
        raise ValueError("the arm's configuration there depends on rounding (a singular pose)")
    return bool(held.all())


def nearest_margin(arm: Arm, solutions: np.ndarray, q_ref) -> tuple[float, int]:
    """How much nearer (Euclidean, deg) the nearest solution to q_ref is than the next one (another turn of one
    axis within the limits, or another branch), and the axis whose other turn is that next one (-1: a branch).
    A margin under ROUNDING_MARGIN_DEG is a tie (an axis half a turn from q_ref either way): the controller's
    "closest configuration" or "shortest turn" is then decided by rounding. inf where only one solution exists."""
    ref = [float(v) for v in q_ref]
    branches = []  # (distance^2, per axis (best, second best) squared distance) per branch with a solution
    for row in np.asarray(solutions, dtype=float).reshape(-1, 6).tolist():
        if not all(math.isfinite(v) for v in row):
            continue
        per_axis, total = [], 0.0
        for value, near, (low, high) in zip(row, ref, arm.limits_deg, strict=True):
            turns = math.floor((near - value) / solve.TURN)
            candidates = sorted(
                (v - near) ** 2
                for v in (value + solve.TURN * k for k in (turns - 1, turns, turns + 1, turns + 2))
                if low - solve.LIMIT_SLACK_DEG <= v <= high + solve.LIMIT_SLACK_DEG
            )
            if not candidates:
                break
            per_axis.append((candidates[0], candidates[1] if len(candidates) > 1 else math.inf))
            total += candidates[0]
        else:
            branches.append((total, per_axis))
    if not branches:
        return math.inf, -1
    branches.sort(key=lambda b: b[0])
    best, per_axis = branches[0]
    nearest = math.sqrt(best)
    others = [(math.sqrt(b[0]), -1) for b in branches[1:]]
    others += [(math.sqrt(best - d1 + d2), axis) for axis, (d1, d2) in enumerate(per_axis) if d2 < math.inf]
    if not others:
        return math.inf, -1
    gap, axis = min(others)
    return gap - nearest, axis


def loose(form: str, arm: Arm, solutions: np.ndarray, value, previous) -> tuple[np.ndarray, np.ndarray]:
    """The joints a joint move takes where the program names only the form's kept fields: the solution nearest
    the joints before it among those the kept fields allow (q, branch); ValueError where two are equally near
    (nearest_margin: the controller's choice would be decided by rounding), naming the axis."""
    candidates = FORMS[form].candidates(arm, solutions, value)
    margin, axis = nearest_margin(arm, candidates, previous)
    if margin < ROUNDING_MARGIN_DEG:
        what = f"axis {axis + 1} is half a turn away either way" if axis >= 0 else "two configurations are as near"
        raise ValueError(f"from joints {np.round(np.asarray(previous, dtype=float), 2).tolist()} {what}")
    return solve.nearest(arm, candidates, previous)
