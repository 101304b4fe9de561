"""Joints for poses, batched: the analytic solutions within the limits, and the one nearest given joints."""

from __future__ import annotations

import math

import numpy as np

from codegen.robot.arms import Arm
from codegen.robot.kinematics import ceil_float

TURN = 360.0
# An axis within this of a quadrant or sign boundary (a vertical tool puts a wrist axis at exactly 0) is at the
# boundary: the analytic solution's rounding (1e-12 deg) and a float32 controller's (below 1e-6 deg at the
# bundled cells' boundaries, measured) decide nothing. The configuration there is the boundary's own, as the
# manuals define it (codegen/robot/config.py, "At a boundary").
BOUNDARY_DEG = 1e-6
LIMIT_SLACK_DEG = 1e-9  # a value this far beyond a joint limit is the analytic solution's rounding: inside


def flange_poses(tcp2base: np.ndarray, tcp2flange: np.ndarray) -> np.ndarray:
    """flange2base = tcp2base . inv(tcp2flange), for (..., 4, 4) poses."""
    return tcp2base @ _flange2tcp(tcp2flange)


_TOOLS: dict[bytes, np.ndarray] = {}


def _flange2tcp(tcp2flange: np.ndarray) -> np.ndarray:
    """inv(tcp2flange) of a rigid transform, remembered by its bytes (a cell has a tool or two; a program sets a
    few): every solved move needs it."""
    tcp2flange = np.asarray(tcp2flange, dtype=float)
    key = tcp2flange.tobytes()
    out = _TOOLS.get(key)
    if out is None:
        rot, trans = tcp2flange[:3, :3], tcp2flange[:3, 3]
        out = np.eye(4)
        out[:3, :3] = rot.T
        out[:3, 3] = -rot.T @ trans
        out.flags.writeable = False
        if len(_TOOLS) >= 256:
            _TOOLS.clear()
        _TOOLS[key] = out
    return out


def branches(arm: Arm, flange2base: np.ndarray) -> np.ndarray:
    """The analytic solutions (..., 8, 6) in deg within (-180, 180]; NaN rows where a branch has none."""
    return arm.kin.ik(flange2base)


def inside(arm: Arm, q: np.ndarray) -> np.ndarray:
    low, high = arm.limits[:, 0], arm.limits[:, 1]
    return np.all((q >= low - LIMIT_SLACK_DEG) & (q <= high + LIMIT_SLACK_DEG), axis=-1)


def shift_into(q: np.ndarray, low: np.ndarray) -> np.ndarray:
    """q + 360 k, the smallest such value at or above low (k may be negative)."""
    return q + TURN * np.ceil((low - q) / TURN - 1e-12)


def shift_into_float(q: float, low: float) -> float:
    """shift_into of one finite Python float (the same operations)."""
    return q + TURN * ceil_float((low - q) / TURN - 1e-12)


def inside_float(q: list[float], limits) -> bool:
    """inside for one pose's axis values as Python floats; limits: the arm's limits_deg."""
    return all(low - LIMIT_SLACK_DEG <= v <= high + LIMIT_SLACK_DEG for v, (low, high) in zip(q, limits, strict=True))


def nearest(arm: Arm, solutions: np.ndarray, q_ref: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per pose, the solution (any branch, any turn within the limits) nearest q_ref in joint space
    (Euclidean): how UR's movej and get_inverse_kin(x, qnear) choose, and how any controller's
    linear move continues from the current joints. (..., 8, 6), (..., 6) -> joints (..., 6) (NaN where
    none) and the branch (..., ) (the index of the analytic solution: the arm's configuration; -1: none)."""
    if solutions.ndim == 2 and np.ndim(q_ref) == 1:
        return _nearest_one(arm, solutions, q_ref)
    ref = np.asarray(q_ref, dtype=float)[..., None, :]
    q = solutions + TURN * np.round((ref - solutions) / TURN)  # each axis to the turn nearest the reference
    low, high = arm.limits[:, 0], arm.limits[:, 1]
    q = np.where(q > high, q - TURN, q)  # outside the limits: the next turn towards the inside, if any
    q = np.where(q < low, q + TURN, q)
    ok = inside(arm, q)  # a NaN axis is inside no limits
    with np.errstate(invalid="ignore"):  # outside ones (NaN, inf) are left out by `ok`: inside, q - ref is finite
        offset = q - ref
        distance = np.where(ok, np.sqrt(np.add.reduce(offset * offset, axis=-1)), np.inf)  # np.linalg.norm's sum
    best = np.argmin(distance, axis=-1)
    chosen = np.take_along_axis(q, best[..., None, None], axis=-2)[..., 0, :]
    found = np.isfinite(np.min(distance, axis=-1))
    return np.where(found[..., None], chosen, np.nan), np.where(found, best, -1)


# nearest's answers for one pose, by the exact bytes of what it was given: the interpreter chooses each move's joints
# from its analytic solutions and where the arm stands, and verify's joint check applies the controller's rule to the
# same solutions from the joints it planned, which are the run's own wherever the run is right (about 60 % of the
# single-pose calls of a verified case ask again). Keyed on the values, the answer is the one computed afresh.
_NEAREST: dict[tuple, tuple[Arm, np.ndarray, np.ndarray]] = {}
NEAREST_REMEMBERED = 4096  # a case asks a few dozen; a run's and its check's asks lie within one case


def _nearest_one(arm: Arm, solutions: np.ndarray, q_ref) -> tuple[np.ndarray, np.ndarray]:
    """_nearest_fresh, remembered (see _NEAREST); copies, so that no caller shares an array with another."""
    ref = np.asarray(q_ref, dtype=float)
    key = (id(arm), solutions.shape, solutions.dtype.str, solutions.tobytes(), ref.tobytes())
    hit = _NEAREST.get(key)
    if hit is None or hit[0] is not arm:
        q, branch = _nearest_fresh(arm, solutions, ref)
        if len(_NEAREST) >= NEAREST_REMEMBERED:
            _NEAREST.clear()
        hit = _NEAREST[key] = (arm, q.copy(), branch.copy())
    return hit[1].copy(), hit[2].copy()


def _nearest_fresh(arm: Arm, solutions: np.ndarray, q_ref) -> tuple[np.ndarray, np.ndarray]:
    """nearest for one pose (8, 6) on Python floats, the same steps (round: half to even in both), the
    first of equally near solutions: a run of the interpreter solves one pose at a time."""
    ref = [float(v) for v in q_ref]
    if not all(math.isfinite(v) for v in ref):  # as the batched path: nothing is near a NaN
        return np.full(len(ref), np.nan), np.array(-1)
    limits = arm.limits_deg
    best, best_distance, best_total = -1, math.inf, math.inf
    chosen: list[float] = []
    round_, sqrt = round, math.sqrt
    for index, row in enumerate(solutions.tolist()):
        q = []
        total = 0.0
        for value, near, (low, high) in zip(row, ref, limits, strict=True):
            if total > best_total:  # the sum only grows: this row cannot be nearer than the best so far
                break
            if not -math.inf < value < math.inf:  # NaN: no solution on this branch
                break
            turns = (near - value) / TURN
            k = round_(turns)
            value += TURN * k if k else 0.0 * turns  # 0 turns: np.round's signed zero, so -0.0 stays -0.0
            if value > high:
                value -= TURN
            if value < low:  # after the step down too, as the batched path (a value just over a limit)
                value += TURN
            if not low - LIMIT_SLACK_DEG <= value <= high + LIMIT_SLACK_DEG:
                break
            q.append(value)
            total += (value - near) * (value - near)
        else:
            distance = sqrt(total)
            if distance < best_distance:
                best, best_distance, best_total, chosen = index, distance, total, q
    if best < 0:
        return np.full(len(ref), np.nan), np.array(-1)
    return np.array(chosen), np.array(best)


def first(q: np.ndarray, match: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    index = np.argmax(match, axis=-1)
    chosen = np.take_along_axis(q, index[..., None, None], axis=-2)[..., 0, :]
    found = match.any(axis=-1)
    return np.where(found[..., None], chosen, np.nan), np.where(found, index, -1)


def unreachable_text(arm: Arm, flange2base: np.ndarray) -> str:
    """Why a flange pose has no solution, as far as its place tells: how far it lies from the base against the
    data sheet's reach (beyond it: too far; within it: the orientation, a joint limit or the arm's own column)."""
    x, y, z = (float(v) for v in flange2base[:3, 3])
    distance = math.sqrt(x * x + y * y + z * z)
    at = f"the flange would be at ({x:.0f}, {y:.0f}, {z:.0f}) mm, {distance:,.0f} mm from the base"
    if arm.reach_mm is None:
        return f"{at}; the arm takes it in no configuration within its joint limits"
    if distance > arm.reach_mm:
        return f"{at}, beyond the {arm.model}'s reach of {arm.reach_mm:,g} mm: move the pose (or the arm) closer"
    return (
        f"{at}, within the {arm.model}'s reach of {arm.reach_mm:,g} mm: its orientation, a joint limit or the arm's "
        "own base rules it out; turn the pose or move it away from the base"
    )
