"""Native pose operations of the controllers, computed in float64 from their stored numbers."""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from codegen import poses


def as64(values) -> list[float]:
    return [float(v) for v in values]


def check_finite(values, where: str, what: str) -> None:
    from codegen.dialects.runtime import RunError

    if not all(math.isfinite(float(v)) for v in values):
        raise RunError(f"{where}: {what} has a non-finite component")


@lru_cache(maxsize=4096)
def _ur_matrix(values: tuple[float, ...]) -> np.ndarray:
    m = poses.matrix_from_ur(values)
    m.flags.writeable = False
    return m


def ur_matrix(pose6) -> np.ndarray:
    """UR pose p[x, y, z (m), rx, ry, rz] -> 4x4 mm (cached: taught poses repeat every run)."""
    return _ur_matrix(tuple(as64(pose6)))


def ur_from(m: np.ndarray) -> tuple[float, ...]:
    return poses.ur_from_matrix(m)


@lru_cache(maxsize=4096)
def _zyx_matrix(values: tuple[float, ...]) -> np.ndarray:
    m = poses.matrix_from_xyzabc(values)
    m.flags.writeable = False
    return m


def zyx_matrix(x, y, z, a, b, c) -> np.ndarray:
    """KUKA FRAME/POS (mm, deg, Rz(A) Ry(B) Rx(C)), cached like ur_matrix."""
    return _zyx_matrix(tuple(as64((x, y, z, a, b, c))))


def zyx_from(m: np.ndarray) -> tuple[float, ...]:
    return poses.xyzabc_from_matrix(m)


def quat_matrix(trans, quat) -> np.ndarray:
    return poses.matrix_from_rotation_translation(poses.rotmat_from_quat(as64(quat)), as64(trans))


def quat_from(m: np.ndarray) -> tuple[float, ...]:
    return tuple(float(v) for v in poses.quat_from_rotmat(m[:3, :3]))


def quat_multiply(q1, q2) -> tuple[float, ...]:
    w1, x1, y1, z1 = as64(q1)
    w2, x2, y2, z2 = as64(q2)
    return (
        w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
        w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
        w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
        w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2,
    )


def quat_rotate(q, v) -> tuple[float, ...]:
    rot = poses.rotmat_from_quat(as64(q))
    return tuple(float(c) for c in rot @ np.array(as64(v)))


def quat_from_zyx_deg(z, y, x) -> tuple[float, ...]:
    """OrientZYX(z, y, x): rotation Rz(z) Ry(y) Rx(x), degrees."""
    hz, hy, hx = (math.radians(float(v)) / 2 for v in (z, y, x))
    qz = (math.cos(hz), 0.0, 0.0, math.sin(hz))
    qy = (math.cos(hy), 0.0, math.sin(hy), 0.0)
    qx = (math.cos(hx), math.sin(hx), 0.0, 0.0)
    return quat_multiply(quat_multiply(qz, qy), qx)
