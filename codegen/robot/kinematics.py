"""The Kinematics protocol every arm family implements, and the batched numpy helpers the families share."""

from __future__ import annotations

import math
from typing import Protocol, runtime_checkable

import numpy as np

BRANCHES = 8  # analytic solutions per pose: shoulder (2) x elbow (2) x wrist (2)
ACOS_SLACK = 1e-12  # |cos| up to 1 + this is rounding (a stretched or just reachable pose), beyond it unreachable
SQRT_SLACK = 1e-9  # mm^2: a negative radicand down to -this is rounding, below it unreachable
# ik of at most this many poses runs pose by pose on Python floats (math module) instead of numpy: a numpy call
# costs about 0.5 us whatever its size, so for a few poses its overhead outweighs the vectorisation (the
# interpreter and the verifier ask for 1 to 4 poses at a time; the two paths cost the same at about 6 poses).
# Both paths are the same formulas (tests/robot/test_robot_kinematics_paths.py compares them).
SMALL_BATCH = 6
# larger batches run through numpy in chunks of this many poses: the temporaries then stay in the CPU's cache
# (10,000 poses at once spend a third of the time on fresh memory)
CHUNK = 2048


@runtime_checkable
class Kinematics(Protocol):
    """An arm's closed-form kinematics in the controller's own axis values (deg) and base frame (mm).

    fk:  (..., 6) axis values -> (..., 4, 4) flange2base.
    ik:  (..., 4, 4) flange2base -> (..., 8, 6) axis values wrapped to (-180, 180], one row per branch in
         the family's documented fixed order, a row of NaN where that branch has no solution; pose by pose up to
         SMALL_BATCH poses, batched in numpy beyond (batched=True or False: that path whatever the number).
    wrist_center: (..., 6) axis values -> (..., 3) the family's wrist point in the base frame.
    link_frames: (..., 6) axis values -> (..., 7, 4, 4) a frame per link (0 the base, 6 the flange), base frame.
    """

    def fk(self, joints_deg: np.ndarray) -> np.ndarray: ...

    def ik(self, flange2base: np.ndarray, batched: bool | None = None) -> np.ndarray: ...

    def wrist_center(self, joints_deg: np.ndarray) -> np.ndarray: ...

    def link_frames(self, joints_deg: np.ndarray) -> np.ndarray: ...


# numpy scalars for the helpers below: an operation with a Python float pays for converting it on every call
_HALF_TURN, _TURN = np.array(180.0), np.array(360.0)
_ONE, _MINUS_ONE, _NAN = np.array(1.0), np.array(-1.0), np.array(np.nan)
_ACOS_LIMIT = np.array(1.0 + ACOS_SLACK)


def in_chunks(function, items: np.ndarray, shape: tuple[int, ...]) -> np.ndarray:
    """function(items) for (n, ...) items -> (n, *shape), CHUNK items at a time (the same numbers: every
    operation is per item)."""
    if len(items) <= CHUNK:
        return function(items)
    out = np.empty((len(items), *shape))
    for start in range(0, len(items), CHUNK):
        out[start : start + CHUNK] = function(items[start : start + CHUNK])
    return out


def wrap_deg(angle_deg: np.ndarray) -> np.ndarray:
    """Angles wrapped to (-180, 180] deg (NaN stays NaN)."""
    a = np.asarray(angle_deg, dtype=float)
    return a - _TURN * np.ceil((a - _HALF_TURN) / _TURN)


def acos_clipped(cosine: np.ndarray) -> np.ndarray:
    """arccos, with |cosine| in (1, 1 + ACOS_SLACK] taken as 1 (rounding) and NaN beyond (unreachable)."""
    c = np.asarray(cosine, dtype=float)
    clipped = np.minimum(np.maximum(c, _MINUS_ONE), _ONE, out=np.empty(c.shape))  # np.clip, without its overhead
    np.copyto(clipped, _NAN, where=np.abs(c) > _ACOS_LIMIT)
    return np.arccos(clipped)


def sqrt_clipped(radicand: np.ndarray) -> np.ndarray:
    """sqrt, with a radicand in [-SQRT_SLACK, 0) taken as 0 (rounding) and NaN below (unreachable)."""
    r = np.asarray(radicand, dtype=float)
    r = np.where(r >= -SQRT_SLACK, np.maximum(r, 0.0), np.nan)
    return np.sqrt(r)


def ceil_float(x: float) -> float:
    """np.ceil of one finite Python float, its signed zero included (ceil(-0.5) is -0.0)."""
    c = math.ceil(x)
    return float(c) if c else math.copysign(0.0, x)


def wrap_deg_float(angle_deg: float) -> float:
    """wrap_deg of one finite Python float (the same operations)."""
    return angle_deg - 360.0 * ceil_float((angle_deg - 180.0) / 360.0)


def acos_clipped_float(cosine: float) -> float:
    """acos_clipped of one Python float."""
    if abs(cosine) <= 1.0 + ACOS_SLACK:
        return math.acos(min(max(cosine, -1.0), 1.0))
    return math.nan


def sqrt_clipped_float(radicand: float) -> float:
    """sqrt_clipped of one Python float."""
    return math.sqrt(max(radicand, 0.0)) if radicand >= -SQRT_SLACK else math.nan


def trig_table(angle: np.ndarray) -> np.ndarray:
    """(..., 5): cos, sin, -sin, 1, 0 of angle (rad): every entry of a rotation about one axis, so that
    rotations are gathered (ROT_Z, ZY_FACTORS) by one indexing instead of stacking nine arrays."""
    angle = np.asarray(angle, dtype=float)
    out = np.empty((*angle.shape, 5))
    np.cos(angle, out=out[..., 0])
    np.sin(angle, out=out[..., 1])
    np.negative(out[..., 1], out=out[..., 2])
    out[..., 3:] = _ONE_ZERO
    return out


_ONE_ZERO = np.array([1.0, 0.0])
ROT_Z = np.array([0, 2, 4, 1, 0, 4, 4, 4, 3])  # trig_table(a)[..., ROT_Z]: Rz(a) flattened, [[c, -s, 0], ...]
# Rz(a) @ Ry(b) = [[ca cb, -sa, ca sb], [sa cb, ca, sa sb], [-sb, 0, cb]] flattened: entry by entry the
# product of trig_table(a)[..., ZY_FACTORS[0]] and trig_table(b)[..., ZY_FACTORS[1]], i.e. of
# [[ca, -sa, ca], [sa, ca, sa], [1, 0, 1]] and [[cb, 1, sb], [cb, 1, sb], [-sb, 1, cb]] (the matrix product's
# entries exactly: each is one product, its other terms are exact zeros)
ZY_FACTORS = np.array([[0, 2, 0, 1, 0, 1, 3, 4, 3], [0, 3, 1, 0, 3, 1, 2, 3, 0]])


def finish_ik(joints_deg: np.ndarray) -> np.ndarray:
    """wrap_deg(joints_deg) with every row (last axis) that holds a NaN made all NaN (a branch is whole or absent),
    in place on joints_deg (a float array the caller owns), in few numpy calls for the few poses a call often has."""
    a = joints_deg
    t = a - _HALF_TURN
    t /= _TURN
    np.ceil(t, out=t)
    t *= _TURN
    a -= t  # wrap_deg; a wrapped angle is finite or NaN and never -0 (x - x is +0)
    # 0 times a row's sum is +-0 (adding it changes no angle) where the row is complete, NaN where it is not
    a += np.add.reduce(a, axis=-1, keepdims=True) * 0.0
    return a
