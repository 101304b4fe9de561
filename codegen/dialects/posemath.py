"""Native pose operations of the controllers, computed in float64 from their stored numbers.

The scalar twin of `codegen.poses`: an operation both modules have carries the same name in both
(`matrix_from_ur`, `rotmat_from_quat`, `zyx_deg_from_rotmat`, ...; see that module's docstring for
the vocabulary and the frame convention). Here a rotmat is a row-major 9-tuple of floats and a
matrix is a 4x4 float64 numpy array built from it; the functions are plain Python because the
interpreters call them many thousand times per verify run. Operations codegen.poses lacks keep
controller-flavoured names (`quat_multiply`, `quat_rotate`, `quat_from_zyx_deg`, `ur_concat`,
`xyzabc_concat`). tests/test_posemath.py checks every twin against codegen.poses.
"""

from __future__ import annotations

import math

import numpy as np

from codegen import poses
from codegen.exactcache import exact_cache
from codegen.poses import wrap_deg


def as64(values) -> list[float]:
    return list(map(float, values))


def check_finite(values, where: str, what: str) -> None:
    if math.isfinite(sum(map(float, values))):  # float32 values: the sum cannot overflow
        return
    if not all(math.isfinite(float(v)) for v in values):
        from codegen.dialects.core.values import RunError

        raise RunError(f"{where}: {what} has a non-finite component")


@exact_cache(maxsize=4096)
def _matrix_from_ur_cached(values: tuple[float, ...]) -> np.ndarray:
    m = poses.matrix_from_ur(values)
    m.flags.writeable = False
    return m


def matrix_from_ur_cached(pose) -> np.ndarray:
    """codegen.poses.matrix_from_ur itself (numpy floats), memoised and read-only: taught poses repeat every run.

    Not the same floats as the scalar `matrix_from_ur` below (the rotation is summed differently);
    URScript pose_inv and pose_add use this one.
    """
    return _matrix_from_ur_cached(tuple(as64(pose)))


# Matrix -> pose: the numpy functions themselves, under their own names.
ur_from_matrix = poses.ur_from_matrix
xyzabc_from_matrix = poses.xyzabc_from_matrix


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
    """v turned by the (normalised) quaternion q: v + 2w (u x v) + 2 u x (u x v), u = (x, y, z)."""
    w, x, y, z = map(float, q)
    n = math.sqrt(w * w + x * x + y * y + z * z)
    w, x, y, z = w / n, x / n, y / n, z / n
    vx, vy, vz = map(float, v)
    tx, ty, tz = 2.0 * (y * vz - z * vy), 2.0 * (z * vx - x * vz), 2.0 * (x * vy - y * vx)
    return (
        vx + w * tx + (y * tz - z * ty),
        vy + w * ty + (z * tx - x * tz),
        vz + w * tz + (x * ty - y * tx),
    )


def quat_from_zyx_deg(z, y, x) -> tuple[float, ...]:
    """OrientZYX(z, y, x): rotation Rz(z) Ry(y) Rx(x), degrees."""
    hz, hy, hx = math.radians(float(z)) / 2, math.radians(float(y)) / 2, math.radians(float(x)) / 2
    cz, sz, cy, sy, cx, sx = math.cos(hz), math.sin(hz), math.cos(hy), math.sin(hy), math.cos(hx), math.sin(hx)
    return (  # qz qy qx multiplied out
        cz * cy * cx + sz * sy * sx,
        cz * cy * sx - sz * sy * cx,
        cz * sy * cx + sz * cy * sx,
        sz * cy * cx - cz * sy * sx,
    )


# --- pure-Python fast paths (the interpreters call these many thousand times per verify run) ----
# A rotmat is a 9-tuple, row-major. Tested against codegen.poses in tests/test_posemath.py.


def rotmat_from_rotvec(rv) -> tuple[float, ...]:
    """As codegen.poses.rotmat_from_rotvec (first order below 1e-12 rad)."""
    rx, ry, rz = rv
    angle = math.sqrt(rx * rx + ry * ry + rz * rz)
    if angle < 1e-12:
        return (1.0, -rz, ry, rz, 1.0, -rx, -ry, rx, 1.0)
    kx, ky, kz = rx / angle, ry / angle, rz / angle
    s, c = math.sin(angle), math.cos(angle)
    v = 1.0 - c
    return (
        c + kx * kx * v, kx * ky * v - kz * s, kx * kz * v + ky * s,
        ky * kx * v + kz * s, c + ky * ky * v, ky * kz * v - kx * s,
        kz * kx * v - ky * s, kz * ky * v + kx * s, c + kz * kz * v,
    )  # fmt: skip


def quat_from_rotmat(r) -> tuple[float, float, float, float]:
    """Shepperd's method, unit quaternion of the sign `codegen.poses.shown_quat` (as codegen.poses.quat_from_rotmat)."""
    m00, m01, m02, m10, m11, m12, m20, m21, m22 = r
    trace = m00 + m11 + m22
    best = max(trace, m00, m11, m22)
    if best == trace:
        s = 2.0 * math.sqrt(max(1.0 + trace, 0.0))
        q = (0.25 * s, (m21 - m12) / s, (m02 - m20) / s, (m10 - m01) / s)
    elif best == m00:
        s = 2.0 * math.sqrt(max(1.0 + m00 - m11 - m22, 0.0))
        q = ((m21 - m12) / s, 0.25 * s, (m01 + m10) / s, (m02 + m20) / s)
    elif best == m11:
        s = 2.0 * math.sqrt(max(1.0 + m11 - m00 - m22, 0.0))
        q = ((m02 - m20) / s, (m01 + m10) / s, 0.25 * s, (m12 + m21) / s)
    else:
        s = 2.0 * math.sqrt(max(1.0 + m22 - m00 - m11, 0.0))
        q = ((m10 - m01) / s, (m02 + m20) / s, (m12 + m21) / s, 0.25 * s)
    n = math.sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3])
    return poses.shown_quat((q[0] / n, q[1] / n, q[2] / n, q[3] / n))


def rotvec_from_rotmat(r) -> tuple[float, float, float]:
    """As codegen.poses.rotvec_from_rotmat: angle in [0, pi], from the w >= 0 quaternion."""
    w, x, y, z = quat_from_rotmat(r)
    if w < 0:
        w, x, y, z = -w, -x, -y, -z
    norm_v = math.sqrt(x * x + y * y + z * z)
    if norm_v < 1e-12:
        return (2.0 * x, 2.0 * y, 2.0 * z)
    angle = 2.0 * math.atan2(norm_v, w)
    return (x / norm_v * angle, y / norm_v * angle, z / norm_v * angle)


def rotmat_mul(a, b) -> tuple[float, ...]:
    a0, a1, a2, a3, a4, a5, a6, a7, a8 = a
    b0, b1, b2, b3, b4, b5, b6, b7, b8 = b
    return (
        a0 * b0 + a1 * b3 + a2 * b6, a0 * b1 + a1 * b4 + a2 * b7, a0 * b2 + a1 * b5 + a2 * b8,
        a3 * b0 + a4 * b3 + a5 * b6, a3 * b1 + a4 * b4 + a5 * b7, a3 * b2 + a4 * b5 + a5 * b8,
        a6 * b0 + a7 * b3 + a8 * b6, a6 * b1 + a7 * b4 + a8 * b7, a6 * b2 + a7 * b5 + a8 * b8,
    )  # fmt: skip


def rotmat_apply(r, v) -> tuple[float, float, float]:
    x, y, z = v
    return (r[0] * x + r[1] * y + r[2] * z, r[3] * x + r[4] * y + r[5] * z, r[6] * x + r[7] * y + r[8] * z)


def concat_rotmat_translation(ra, ta, rb, tb) -> tuple[tuple[float, ...], tuple[float, float, float]]:
    """codegen.poses.concat on (rotmat, translation) pairs: (Ra, ta) . (Rb, tb) = (Ra Rb, Ra tb + ta)."""
    x, y, z = rotmat_apply(ra, tb)
    return rotmat_mul(ra, rb), (x + ta[0], y + ta[1], z + ta[2])


@exact_cache(maxsize=4096)  # taught poses repeat in every run
def rotmat_from_zyx_deg(a: float, b: float, c: float) -> tuple[float, ...]:
    ca, sa = math.cos(math.radians(a)), math.sin(math.radians(a))
    cb, sb = math.cos(math.radians(b)), math.sin(math.radians(b))
    cc, sc = math.cos(math.radians(c)), math.sin(math.radians(c))
    return (
        ca * cb, ca * sb * sc - sa * cc, ca * sb * cc + sa * sc,
        sa * cb, sa * sb * sc + ca * cc, sa * sb * cc - ca * sc,
        -sb, cb * sc, cb * cc,
    )  # fmt: skip


def zyx_deg_from_rotmat(r) -> tuple[float, float, float]:
    """As codegen.poses.zyx_deg_from_rotmat (c = 0 at gimbal lock, a and c in (-180, 180])."""
    cb = math.hypot(r[0], r[3])
    b = math.atan2(-r[6], cb)
    if cb > 1e-9:
        a, c = math.atan2(r[3], r[0]), math.atan2(r[7], r[8])
    else:
        a, c = math.atan2(-r[1], r[4]), 0.0
    return wrap_deg(math.degrees(a)), math.degrees(b), wrap_deg(math.degrees(c))


def rotmat_from_quat(q) -> tuple[float, ...]:
    """As codegen.poses.rotmat_from_quat (q normalised first, scalar first)."""
    w, x, y, z = q
    n = math.sqrt(w * w + x * x + y * y + z * z)
    w, x, y, z = w / n, x / n, y / n, z / n
    return (
        1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),
        2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
        2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y),
    )  # fmt: skip


def matrix_from_rotation_translation(r, t) -> np.ndarray:
    return np.array(
        [[r[0], r[1], r[2], t[0]], [r[3], r[4], r[5], t[1]], [r[6], r[7], r[8], t[2]], [0.0, 0.0, 0.0, 1.0]]
    )


def matrix_from_ur(pose) -> np.ndarray:
    """UR p[x, y, z (m), rx, ry, rz] -> 4x4 mm, as codegen.poses.matrix_from_ur (scalar rotation)."""
    values = as64(pose)
    return matrix_from_rotation_translation(rotmat_from_rotvec(values[3:]), [v * 1000.0 for v in values[:3]])


def matrix_from_xyzabc(pose) -> np.ndarray:
    """[X, Y, Z, A, B, C] (mm, deg, Rz(A) Ry(B) Rx(C)) -> 4x4, as codegen.poses.matrix_from_xyzabc."""
    v = as64(pose)
    return matrix_from_rotation_translation(rotmat_from_zyx_deg(*v[3:]), v[:3])


def matrix_from_abb(pose) -> np.ndarray:
    """ABB [x, y, z, q1, q2, q3, q4] (mm, quaternion scalar first) -> 4x4, as codegen.poses.matrix_from_abb."""
    v = as64(pose)
    return matrix_from_rotation_translation(rotmat_from_quat(v[3:7]), v[:3])


def ur_concat(a, b) -> tuple[float, ...]:
    """URScript pose_trans(a, b) = ur_from_matrix(matrix_from_ur(a) @ matrix_from_ur(b)), in float64."""
    ra, ta = rotmat_from_rotvec(as64(a[3:])), as64(a[:3])
    rb, tb = rotmat_from_rotvec(as64(b[3:])), as64(b[:3])
    r, t = concat_rotmat_translation(ra, ta, rb, tb)
    return (*t, *rotvec_from_rotmat(r))


def xyzabc_concat(a, b) -> tuple[float, ...]:
    """a . b for poses [X, Y, Z, A, B, C] (mm, deg) = xyzabc_from_matrix(matrix_from_xyzabc(a) @ ...(b))."""
    a, b = as64(a), as64(b)
    r, t = concat_rotmat_translation(rotmat_from_zyx_deg(*a[3:]), a[:3], rotmat_from_zyx_deg(*b[3:]), b[:3])
    return (*t, *zyx_deg_from_rotmat(r))
