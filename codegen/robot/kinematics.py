"""The Kinematics protocol every arm family implements, and the batched numpy helpers the families share."""

from __future__ import annotations

from typing import Protocol, runtime_checkable

import numpy as np

BRANCHES = 8  # analytic solutions per pose: shoulder (2) x elbow (2) x wrist (2)
ACOS_SLACK = 1e-12  # |cos| up to 1 + this is rounding (a stretched or just reachable pose), beyond it unreachable
SQRT_SLACK = 1e-9  # mm^2: a negative radicand down to -this is rounding, below it unreachable


@runtime_checkable
class Kinematics(Protocol):
    """An arm's closed-form kinematics in the controller's own axis values (deg) and base frame (mm).

    fk:  (..., 6) axis values -> (..., 4, 4) flange2base.
    ik:  (..., 4, 4) flange2base -> (..., 8, 6) axis values wrapped to (-180, 180], one row per branch in
         the family's documented fixed order, a row of NaN where that branch has no solution.
    wrist_center: (..., 6) axis values -> (..., 3) the family's wrist point in the base frame.
    """

    def fk(self, joints_deg: np.ndarray) -> np.ndarray: ...

    def ik(self, flange2base: np.ndarray) -> np.ndarray: ...

    def wrist_center(self, joints_deg: np.ndarray) -> np.ndarray: ...


def wrap_deg(angle_deg: np.ndarray) -> np.ndarray:
    """Angles wrapped to (-180, 180] deg (NaN stays NaN)."""
    a = np.asarray(angle_deg, dtype=float)
    return a - 360.0 * np.ceil((a - 180.0) / 360.0)


def acos_clipped(cosine: np.ndarray) -> np.ndarray:
    """arccos, with |cosine| in (1, 1 + ACOS_SLACK] taken as 1 (rounding) and NaN beyond (unreachable)."""
    c = np.asarray(cosine, dtype=float)
    c = np.where(np.abs(c) <= 1.0 + ACOS_SLACK, np.minimum(np.maximum(c, -1.0), 1.0), np.nan)  # = np.clip, faster
    return np.arccos(c)


def sqrt_clipped(radicand: np.ndarray) -> np.ndarray:
    """sqrt, with a radicand in [-SQRT_SLACK, 0) taken as 0 (rounding) and NaN below (unreachable)."""
    r = np.asarray(radicand, dtype=float)
    r = np.where(r >= -SQRT_SLACK, np.maximum(r, 0.0), np.nan)
    return np.sqrt(r)


def trig_table(angle: np.ndarray) -> np.ndarray:
    """(..., 5): cos, sin, -sin, 1, 0 of angle (rad): every entry of a rotation about one axis, to gather
    rotations from (ROT_Z, ROT_Y, rot_zy) with one indexing instead of stacking nine arrays."""
    angle = np.asarray(angle, dtype=float)
    out = np.empty((*angle.shape, 5))
    np.cos(angle, out=out[..., 0])
    np.sin(angle, out=out[..., 1])
    np.negative(out[..., 1], out=out[..., 2])
    out[..., 3:] = _ONE_ZERO
    return out


_ONE_ZERO = np.array([1.0, 0.0])
ROT_Z = np.array([0, 2, 4, 1, 0, 4, 4, 4, 3])  # trig_table(a)[..., ROT_Z]: rot_z(a) flattened, [[c, -s, 0], ...]
ROT_Y = np.array([0, 4, 1, 4, 3, 4, 2, 4, 0])  # [[c, 0, s], [0, 1, 0], [-s, 0, c]]
# rot_z(a) @ rot_y(b) = [[ca cb, -sa, ca sb], [sa cb, ca, sa sb], [-sb, 0, cb]]: entry by entry a product of
# [[ca, -sa, ca], [sa, ca, sa], [1, 0, 1]] and [[cb, 1, sb], [cb, 1, sb], [-sb, 1, cb]]
_ZY_LEFT = np.array([0, 2, 0, 1, 0, 1, 3, 4, 3])
_ZY_RIGHT = np.array([0, 3, 1, 0, 3, 1, 2, 3, 0])


def rot_z(angle: np.ndarray) -> np.ndarray:
    """(..., 3, 3) rotations about z by angle (rad)."""
    return trig_table(angle)[..., ROT_Z].reshape(*np.shape(angle), 3, 3)


def rot_y(angle: np.ndarray) -> np.ndarray:
    """(..., 3, 3) rotations about y by angle (rad)."""
    return trig_table(angle)[..., ROT_Y].reshape(*np.shape(angle), 3, 3)


def rot_zy(table_z: np.ndarray, table_y: np.ndarray) -> np.ndarray:
    """(..., 3, 3) rot_z(a) @ rot_y(b) from trig_table(a) and trig_table(b) (broadcast): the matrix product's
    entries (each a single product, its other terms exact zeros) without the product."""
    entries = table_z[..., _ZY_LEFT] * table_y[..., _ZY_RIGHT]
    return entries.reshape(*entries.shape[:-1], 3, 3)


def homogeneous(rotation: np.ndarray, translation: np.ndarray) -> np.ndarray:
    """(..., 4, 4) from (..., 3, 3) rotations and (..., 3) translations."""
    shape = rotation.shape[:-2]
    out = np.zeros((*shape, 4, 4))
    out[..., :3, :3] = rotation
    out[..., :3, 3] = translation
    out[..., 3, 3] = 1.0
    return out


def nan_incomplete_rows(joints: np.ndarray) -> np.ndarray:
    """Rows (last axis) with any NaN become all NaN, so a branch is either whole or absent."""
    return np.where(np.isnan(joints).any(axis=-1, keepdims=True), np.nan, joints)
