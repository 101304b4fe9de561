"""Pose conventions to and from 4x4 homogeneous matrices (float64, millimetres).

Vocabulary. A *matrix* is a 4x4 homogeneous transform (float64 numpy array, millimetres); a
*rotmat* is its 3x3 rotation part. Conversions are named as in pytransform3d:
`matrix_from_<convention>` / `<convention>_from_matrix` for whole poses (`xyzabc`, `dtrans`, `ur`,
`abb`) and `rotmat_from_<rotation>` / `<rotation>_from_rotmat` for rotations (`zyx_deg`, `rotvec`,
`quat`, scalar first). `codegen.dialects.posemath`, the interpreters' scalar fast path, uses the
same names for the same operations (its rotmat is a row-major 9-tuple). Angles are wrapped by
`wrap_deg`, defined here once.

Frame convention (pytransform3d's, used for every variable name in codegen): a transform named
`A2B` maps coordinates in frame A to coordinates in frame B, p_B = A2B @ p_A; equivalently it is the
pose of frame A expressed in frame B. So `tcp2base` is where the tool is in the robot base frame, and
a taught pose is a `pose2base`. `concat(A2B, B2C, C2D)` is `A2D` (= C2D @ B2C @ A2B), as in
pytransform3d, so a chain reads in the order of its frames; `invert(A2B)` is `B2A`.
"""

from __future__ import annotations

import math

import numpy as np

from codegen.decimals import format_literal

_EPS = 1e-12


def rotz(angle_rad: float) -> np.ndarray:
    c, s = math.cos(angle_rad), math.sin(angle_rad)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def roty(angle_rad: float) -> np.ndarray:
    c, s = math.cos(angle_rad), math.sin(angle_rad)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def rotx(angle_rad: float) -> np.ndarray:
    c, s = math.cos(angle_rad), math.sin(angle_rad)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def matrix_from_rotation_translation(rot: np.ndarray, trans) -> np.ndarray:
    out = np.zeros((4, 4))
    out[:3, :3] = rot
    out[:3, 3] = trans
    out[3, 3] = 1.0
    return out


def concat(*transforms: np.ndarray) -> np.ndarray:
    """concat(A2B, B2C, ...) = A2Z, the product ... @ B2C @ A2B, as a new array (pytransform3d's order)."""
    if not transforms:
        return np.eye(4)
    out = np.array(transforms[-1], dtype=float)
    for m in reversed(transforms[:-1]):
        out = out @ m
    return out


def invert(transform: np.ndarray) -> np.ndarray:
    """Rigid inverse [R^T | -R^T t]: invert(A2B) = B2A."""
    rot = transform[:3, :3].T
    return matrix_from_rotation_translation(rot, -rot @ transform[:3, 3])


# --- Euler Z-Y-X (A, B, C; the dtrans rx, ry, rz with rz outermost) ---------------------------


def rotmat_from_zyx_deg(a: float, b: float, c: float) -> np.ndarray:
    return rotz(math.radians(a)) @ roty(math.radians(b)) @ rotx(math.radians(c))


def zyx_deg_from_rotmat(rot: np.ndarray) -> tuple[float, float, float]:
    """R = Rz(a)Ry(b)Rx(c) -> (a, b, c) deg, a and c in (-180, 180]; at b = +-90 deg c is set 0."""
    sb = -rot[2, 0]
    cb = math.hypot(rot[0, 0], rot[1, 0])
    b = math.atan2(sb, cb)
    if cb > 1e-9:
        a = math.atan2(rot[1, 0], rot[0, 0])
        c = math.atan2(rot[2, 1], rot[2, 2])
    else:
        # Gimbal lock: only a - c (b = +90) or a + c (b = -90) is defined; choose c = 0.
        c = 0.0
        a = math.atan2(-rot[0, 1], rot[1, 1])
    return wrap_deg(math.degrees(a)), math.degrees(b), wrap_deg(math.degrees(c))


def wrap_deg(angle: float) -> float:
    """Angle in degrees into (-180, 180]; never -0.0 (0.0 for -0.0 and for negative multiples of 360)."""
    out = math.remainder(angle, 360.0)
    if out == -180.0:
        out = 180.0
    return out + 0.0  # no -0.0


def matrix_from_xyzabc(pose) -> np.ndarray:
    x, y, z, a, b, c = (float(v) for v in pose)
    return matrix_from_rotation_translation(rotmat_from_zyx_deg(a, b, c), (x, y, z))


def xyzabc_from_matrix(m: np.ndarray) -> tuple[float, ...]:
    a, b, c = zyx_deg_from_rotmat(m[:3, :3])
    return (float(m[0, 3]), float(m[1, 3]), float(m[2, 3]), a, b, c)


def matrix_from_dtrans(pose) -> np.ndarray:
    """dtrans order [x, y, z, rx, ry, rz] with R = Rz(rz) Ry(ry) Rx(rx)."""
    x, y, z, rx, ry, rz = (float(v) for v in pose)
    return matrix_from_xyzabc((x, y, z, rz, ry, rx))


def dtrans_from_matrix(m: np.ndarray) -> tuple[float, ...]:
    x, y, z, a, b, c = xyzabc_from_matrix(m)
    return (x, y, z, c, b, a)


# --- Rotation vector (UR) ---------------------------------------------------------------------


def rotmat_from_rotvec(rv) -> np.ndarray:
    rv = np.asarray(rv, dtype=float)
    angle = float(np.linalg.norm(rv))
    if angle < _EPS:
        k = np.array([[0, -rv[2], rv[1]], [rv[2], 0, -rv[0]], [-rv[1], rv[0], 0]])
        return np.eye(3) + k
    axis = rv / angle
    kx, ky, kz = axis
    k = np.array([[0, -kz, ky], [kz, 0, -kx], [-ky, kx, 0]])
    return np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * (k @ k)


def rotvec_from_rotmat(rot: np.ndarray) -> np.ndarray:
    """Angle in [0, pi]; robust near 0 (first-order) and near pi (axis from the symmetric part)."""
    quat = quat_from_rotmat(rot)
    w, v = quat[0], quat[1:]
    if w < 0:
        w, v = -w, -v
    norm_v = float(np.linalg.norm(v))
    if norm_v < _EPS:
        return 2.0 * v  # small angle: rotvec ~ 2 * vector part
    angle = 2.0 * math.atan2(norm_v, w)
    return v / norm_v * angle


def matrix_from_ur(pose) -> np.ndarray:
    """UR p[x, y, z, rx, ry, rz]: metres and rotation vector (rad) -> matrix in mm."""
    x, y, z, rx, ry, rz = (float(v) for v in pose)
    return matrix_from_rotation_translation(rotmat_from_rotvec((rx, ry, rz)), (x * 1000.0, y * 1000.0, z * 1000.0))


def ur_from_matrix(m: np.ndarray) -> tuple[float, ...]:
    rv = rotvec_from_rotmat(m[:3, :3])
    return (
        float(m[0, 3]) / 1000.0,
        float(m[1, 3]) / 1000.0,
        float(m[2, 3]) / 1000.0,
        float(rv[0]),
        float(rv[1]),
        float(rv[2]),
    )


# --- Quaternion, scalar first (ABB) -----------------------------------------------------------


def rotmat_from_quat(q) -> np.ndarray:
    w, x, y, z = (float(v) for v in q)
    n = math.sqrt(w * w + x * x + y * y + z * z)
    w, x, y, z = w / n, x / n, y / n, z / n
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def quat_from_rotmat(rot: np.ndarray) -> np.ndarray:
    """Shepperd's method; returns the unit quaternion of sign `shown_quat` (w >= 0)."""
    m = rot
    trace = m[0, 0] + m[1, 1] + m[2, 2]
    candidates = (trace, m[0, 0], m[1, 1], m[2, 2])
    i = int(np.argmax(candidates))
    if i == 0:
        s = 2.0 * math.sqrt(max(1.0 + trace, 0.0))
        q = (0.25 * s, (m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s)
    elif i == 1:
        s = 2.0 * math.sqrt(max(1.0 + m[0, 0] - m[1, 1] - m[2, 2], 0.0))
        q = ((m[2, 1] - m[1, 2]) / s, 0.25 * s, (m[0, 1] + m[1, 0]) / s, (m[0, 2] + m[2, 0]) / s)
    elif i == 2:
        s = 2.0 * math.sqrt(max(1.0 + m[1, 1] - m[0, 0] - m[2, 2], 0.0))
        q = ((m[0, 2] - m[2, 0]) / s, (m[0, 1] + m[1, 0]) / s, 0.25 * s, (m[1, 2] + m[2, 1]) / s)
    else:
        s = 2.0 * math.sqrt(max(1.0 + m[2, 2] - m[0, 0] - m[1, 1], 0.0))
        q = ((m[1, 0] - m[0, 1]) / s, (m[0, 2] + m[2, 0]) / s, (m[1, 2] + m[2, 1]) / s, 0.25 * s)
    quat = np.array(q)
    quat /= np.linalg.norm(quat)
    return np.array(shown_quat(quat))


# A component this small is a tie for the sign rule: above the float32 noise of an interpreted pose
# (1.2e-7 per unit value), so the reference (float64) and `codegen run` (float32) pick the same sign.
QUAT_SIGN_TIE = 1e-6


def shown_quat(quat) -> tuple[float, float, float, float]:
    """The one sign of q and -q shown: the first of w, x, y, z not within QUAT_SIGN_TIE of 0 is positive.

    So w > 0 away from a half turn; at a half turn (w ~ 0) the first clear axis component decides."""
    values = tuple(float(v) for v in quat)
    sign = _shown_sign(values)
    return tuple(sign * v + 0.0 for v in values)


def _shown_sign(quat: tuple[float, ...]) -> float:
    """-1 where `shown_quat` shows -q, else 1."""
    lead = next((v for v in quat if abs(v) > QUAT_SIGN_TIE), 1.0)
    return -1.0 if lead < 0 else 1.0


def shown_rotvec(rv) -> tuple[float, float, float]:
    """The one of a rotation's two rotation vectors at a half turn shown: that of its `shown_quat`.

    Away from a half turn the vector of angle in [0, pi) is shown. At a half turn (the quaternion's w within
    QUAT_SIGN_TIE of 0, float32 noise included) rv and rv * (angle - 2 pi) / angle are one rotation; the one
    whose first clear component is positive is shown, as for the quaternion."""
    rv = np.asarray(rv, dtype=float)
    angle = float(np.linalg.norm(rv))
    if angle < _EPS:
        return tuple(float(v) + 0.0 for v in rv)
    quat = (math.cos(angle / 2.0), *(float(v) * math.sin(angle / 2.0) / angle for v in rv))
    scale = 1.0 if _shown_sign(quat) > 0 else (angle - 2.0 * math.pi) / angle  # -q: angle 2 pi - angle about -axis
    return tuple(float(v) * scale + 0.0 for v in rv)


def matrix_from_abb(pose) -> np.ndarray:
    """ABB [x, y, z, q1, q2, q3, q4]: mm and quaternion, scalar first."""
    x, y, z = (float(v) for v in pose[:3])
    return matrix_from_rotation_translation(rotmat_from_quat(pose[3:7]), (x, y, z))


def abb_from_matrix(m: np.ndarray) -> tuple[float, ...]:
    q = quat_from_rotmat(m[:3, :3])
    return (float(m[0, 3]), float(m[1, 3]), float(m[2, 3]), *(float(v) for v in q))


# --- Registry of formats used by cell files and by `codegen correct` -------------------------

POSE_FORMATS = {
    # name: (values per pose, to-matrix, from-matrix, description)
    "xyzabc": (6, matrix_from_xyzabc, xyzabc_from_matrix, "x y z mm, a b c deg, R = Rz(a)Ry(b)Rx(c)"),
    "ur": (6, matrix_from_ur, ur_from_matrix, "x y z m, rotation vector rx ry rz rad"),
    "abb": (7, matrix_from_abb, abb_from_matrix, "x y z mm, quaternion q1..q4 scalar first"),
    "dtrans": (6, matrix_from_dtrans, dtrans_from_matrix, "x y z mm, rx ry rz deg, R = Rz(rz)Ry(ry)Rx(rx)"),
}


# Decimals used when a pose is printed (program data and text reports): 0.1 um for mm, 1e-6 deg,
# 1e-9 for unit quantities (rotation vector rad, quaternion), 0.1 um for UR metres.
FORMAT_DECIMALS = {
    "ur": (7, 7, 7, 9, 9, 9),
    "xyzabc": (4, 4, 4, 6, 6, 6),
    "abb": (4, 4, 4, 9, 9, 9, 9),
    "dtrans": (4, 4, 4, 6, 6, 6),
}


def shown_values(values, fmt: str) -> tuple[float, ...]:
    """A pose in format fmt as reports show it: a half turn of the one sign (`shown_quat`, `shown_rotvec`)."""
    values = tuple(float(v) for v in values)
    if fmt == "ur":
        return (*values[:3], *shown_rotvec(values[3:6]))
    if fmt == "abb":
        return (*values[:3], *shown_quat(values[3:7]))
    return values


def pose_text(values, fmt: str) -> str:
    """The one text of a pose in reports (`codegen correct`, `codegen run`): FORMAT_DECIMALS, no '-0', shown sign."""
    shown = shown_values(values, fmt)
    return " ".join(format_literal(v, n) for v, n in zip(shown, FORMAT_DECIMALS[fmt], strict=True))


def native_values(values, from_format: str, to_format: str) -> tuple[float, ...]:
    """A taught pose in another format; exact (no round trip) where the formats are reorderings."""
    if from_format == to_format:
        return tuple(values)
    if {from_format, to_format} == {"xyzabc", "dtrans"}:
        x, y, z, u, v, w = values
        return (x, y, z, w, v, u)
    return POSE_FORMATS[to_format][2](POSE_FORMATS[from_format][1](values))


def planar_motions(offsets: np.ndarray) -> np.ndarray:
    """Trans(dx, dy, 0) . Rz(angle) for each row (dx mm, dy mm, angle deg) of offsets: (N, 4, 4)."""
    offsets = np.asarray(offsets, dtype=float)
    angle = np.radians(offsets[:, 2])
    out = np.zeros((len(offsets), 4, 4))
    out[:, 0, 0] = out[:, 1, 1] = np.cos(angle)
    out[:, 1, 0] = np.sin(angle)
    out[:, 0, 1] = -out[:, 1, 0]
    out[:, 2, 2] = out[:, 3, 3] = 1.0
    out[:, 0, 3], out[:, 1, 3] = offsets[:, 0], offsets[:, 1]
    return out
