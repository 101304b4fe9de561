"""UR-type arms (Universal Robots): closed-form, batched forward and inverse kinematics on UR's standard DH table."""

# UR's published standard Denavit-Hartenberg table ("DH Parameters for calculations of kinematics and dynamics",
# Universal Robots support article): alpha = [90, 0, 0, 90, -90, 0] deg, a = [0, a2, a3, 0, 0, 0],
# d = [d1, 0, 0, d4, d5, d6], theta_i = q_i; T_i = Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i). UR writes a2, a3
# negative: at q = 0 the arm lies stretched along base -x.
#
# Base frame: the pose the UR controller reports (teach pendant, get_actual_tcp_pose, get_forward_kin) is DH
# frame 0 itself, not rotated. Source: UniversalRobots/Universal_Robots_ROS2_Description, doc/robot_frames.rst
# ("the frame base is in the same location and orientation as seen by the robot controller. In relation to
# the base_link frame, it is rotated by 180 degrees around the Z-axis") and urdf/ur_macro.xacro, where
# shoulder_pan_joint hangs off base_link_inertia (base_link rotated by pi about z, i.e. the controller's base)
# with the DH-derived origins of config/<model>/default_kinematics.yaml (shoulder at z = d1, no rotation).
# ROS's REP-103 base_link is the frame rotated 180 deg about z; ROS-Industrial universal_robot PR #505
# confirmed base -> tool0 equals the pendant on a UR16e. The flange frame is DH frame 6 (the controller's TCP
# with an all-zero tool offset; ur_description's tool0).
#
# Inverse kinematics (own derivation on this table, the usual structure of UR solvers): the point p5 (axes 5
# and 6 meet) = flange - d6 z6 lies at distance d4 from the plane of joints 2-4, giving q1 (2); z1 . z6 =
# cos q5 (2); q6 from the flange axes' components along z1; q2, q3 as a planar 2R arm (2); q4 the rest.

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from types import SimpleNamespace

import numpy as np

from codegen.robot.kinematics import SMALL_BATCH, acos_clipped, acos_clipped_float, finish_ik, in_chunks

ALPHA_DEG = (90, 0, 0, 90, -90, 0)
COS_ALPHA = (0.0, 1.0, 1.0, 0.0, 0.0, 1.0)  # exact, not cos(pi / 2) = 6e-17
SIN_ALPHA = (1.0, 0.0, 0.0, 1.0, -1.0, 0.0)
WRIST_SINGULAR = 1e-12  # |sin q5| below this: q6 only acts together with q2 + q3 + q4 (see URDH)

# The batched code keeps numpy calls few (a call costs about as much for 1 pose as for 100): per-arm constants
# are cached numpy scalars, and ik writes into one array theta (pose, shoulder, elbow, wrist, axis) whose
# branch axes broadcast.
_EYE4 = np.eye(4)
_PLUS_MINUS = np.array([1.0, -1.0])  # q1 = phi + 90 +- spread; q5 = +-; q3 = +-
_MINUS_PLUS = np.array([-1.0, 1.0])


@dataclass(frozen=True)
class URDH:
    """A UR-type arm by UR's DH lengths (mm, UR's signs: a2, a3 negative). Axis values are the DH angles.

    ik branch order (fixed), index = 4 * shoulder + 2 * elbow + wrist:
      shoulder 0: q1 = atan2(p5y, p5x) + 90 deg + acos(d4 / |p5_xy|) (p5, where axes 5 and 6 meet, on the
                  side the arm stretches to at q2 = 0: x <= 0 in the frame of joint 1), 1: the other root;
      elbow    0: q3 >= 0, 1: q3 < 0;
      wrist    0: q5 >= 0, 1: q5 < 0.
    Singularities (finite answers where reachable): wrist (q5 = 0 or 180, axis 6 parallel to axes 2-4): q6
    and q2..q4 trade off along a circle of joint-4 positions; q6 = 0 is chosen, or where that leaves joint 4
    out of the arm's reach, the q6 that puts joint 4 at the middle of the reach of axes 2-3; shoulder (p5 on
    the cylinder |p5_xy| = d4: both q1 roots meet) and elbow (stretched): cos values up to 1 + 1e-12 are
    taken as 1, the two rows of the pair are then equal. Unreachable: NaN rows.
    """

    d1: float
    a2: float
    a3: float
    d4: float
    d5: float
    d6: float

    @cached_property
    def _k(self) -> SimpleNamespace:
        """Per-arm constants of fk and ik, as numpy scalars and arrays (the same values the formulas need)."""
        d = (self.d1, 0.0, 0.0, self.d4, self.d5, self.d6)
        link_rows = [
            [[0.0, sa, ca, di], [0.0, 0.0, 0.0, 1.0]] for sa, ca, di in zip(SIN_ALPHA, COS_ALPHA, d, strict=True)
        ]
        return SimpleNamespace(
            cos_alpha=np.array(COS_ALPHA)[:, None],  # (link, 1)
            sin_alpha=np.array(SIN_ALPHA)[:, None],
            a=np.array([0.0, self.a2, self.a3, 0.0, 0.0, 0.0])[:, None],
            link_rows=np.array(link_rows)[:, None],  # (link, 1, 2, 4): the last two rows of each link
            d1=np.array(self.d1),
            d4=np.array(self.d4),
            d5=np.array(self.d5),
            d6=np.array(self.d6),
            a2=np.array(self.a2),
            a3=np.array(self.a3),
            a2_squared=np.array(self.a2 * self.a2),
            a3_squared=np.array(self.a3 * self.a3),
            elbow_denominator=np.array(2.0 * self.a2 * self.a3),
            quarter_turn=np.array(math.pi / 2),
        )

    @cached_property
    def _floats(self) -> SimpleNamespace:
        """_k as Python floats, for the pose-by-pose path."""
        return SimpleNamespace(**{name: value.item() for name, value in vars(self._k).items() if value.ndim == 0})

    def _frames(self, joints_deg: np.ndarray, count: int) -> np.ndarray:
        """(..., 4, 4): DH frame `count` in the base frame (1 <= count <= 6)."""
        q = np.asarray(joints_deg, dtype=float)
        frames = in_chunks(lambda chunk: self._frame(chunk, count), q.reshape(-1, 6), (4, 4))
        return frames.reshape(*q.shape[:-1], 4, 4)

    def _frame(self, q: np.ndarray, count: int) -> np.ndarray:
        """DH frame `count` of (n, 6) axis values (deg), batched."""
        q = q.T[:count]
        q = np.radians(q, out=np.empty(q.shape))  # (link, n), contiguous
        k = self._k
        links = np.empty((*q.shape, 4, 4))  # Rz(q) Tz(d) Tx(a) Rx(alpha) per link
        c = np.cos(q, out=links[..., 0, 0])
        s = np.sin(q, out=links[..., 1, 0])
        np.multiply(-s, k.cos_alpha[:count], out=links[..., 0, 1])
        np.multiply(c, k.cos_alpha[:count], out=links[..., 1, 1])
        np.multiply(s, k.sin_alpha[:count], out=links[..., 0, 2])
        np.multiply(-c, k.sin_alpha[:count], out=links[..., 1, 2])
        np.multiply(c, k.a[:count], out=links[..., 0, 3])
        np.multiply(s, k.a[:count], out=links[..., 1, 3])
        links[..., 2:, :] = k.link_rows[:count]  # [0, sa, ca, d], [0, 0, 0, 1]
        out = _EYE4 @ links[0]  # (as the product from the identity: a NaN angle spreads over the matrix)
        for link in links[1:]:
            out = out @ link
        return out

    def fk(self, joints_deg: np.ndarray) -> np.ndarray:
        """(..., 6) axis values (deg) -> (..., 4, 4) flange2base (mm), base = the controller's base frame."""
        return self._frames(joints_deg, 6)

    def link_frames(self, joints_deg: np.ndarray) -> np.ndarray:
        """(..., 7, 4, 4): DH frames 0 (the base) to 6 (the flange) in the base frame, mm. Frame i turns with
        link i (the body after joint i); its z axis is joint i + 1's axis."""
        q = np.radians(np.asarray(joints_deg, dtype=float))
        d = (self.d1, 0.0, 0.0, self.d4, self.d5, self.d6)
        a = (0.0, self.a2, self.a3, 0.0, 0.0, 0.0)
        out = np.empty((*q.shape[:-1], 7, 4, 4))
        out[..., 0, :, :] = np.eye(4)
        for i in range(6):  # Rz(q) Tz(d) Tx(a) Rx(alpha), as _frame builds it
            c, s = np.cos(q[..., i]), np.sin(q[..., i])
            link = np.zeros((*q.shape[:-1], 4, 4))
            link[..., 0, 0], link[..., 1, 0] = c, s
            link[..., 0, 1], link[..., 1, 1] = -s * COS_ALPHA[i], c * COS_ALPHA[i]
            link[..., 0, 2], link[..., 1, 2] = s * SIN_ALPHA[i], -c * SIN_ALPHA[i]
            link[..., 0, 3], link[..., 1, 3] = c * a[i], s * a[i]
            link[..., 2, :] = (0.0, SIN_ALPHA[i], COS_ALPHA[i], d[i])
            link[..., 3, 3] = 1.0
            out[..., i + 1, :, :] = out[..., i, :, :] @ link
        return out

    def wrist_center(self, joints_deg: np.ndarray) -> np.ndarray:
        """(..., 3) where axes 5 and 6 meet (DH frame 5's origin, flange - d6 z6), base frame, mm."""
        return self._frames(joints_deg, 5)[..., :3, 3]

    def ik(self, flange2base: np.ndarray, batched: bool | None = None) -> np.ndarray:
        """(..., 4, 4) flange2base -> (..., 8, 6) axis values (deg, wrapped to (-180, 180]); NaN rows: none.
        batched: numpy's path (True) or pose by pose (False); None: by the number of poses."""
        pose = np.asarray(flange2base, dtype=float)
        return self._ik(pose, scalar=pose.size <= 16 * SMALL_BATCH if batched is None else not batched)

    def _ik(self, pose: np.ndarray, scalar: bool) -> np.ndarray:
        """ik pose by pose on Python floats (scalar; unless math refuses a pose or one needs _singular_q6) or
        batched in numpy."""
        batch = pose.shape[:-2]
        pose = pose.reshape(-1, 4, 4)
        theta = self._theta_floats(pose) if scalar else None
        if theta is None:
            with np.errstate(invalid="ignore", divide="ignore"):
                theta = in_chunks(self._solve, pose, (2, 2, 2, 6))  # (n, shoulder, elbow, wrist, 6)
        return finish_ik(np.degrees(theta).reshape(*batch, 8, 6))

    def _solve(self, pose: np.ndarray) -> np.ndarray:
        """theta (rad) of (n, 4, 4) poses as (n, shoulder, elbow, wrist, axis), batched."""
        k = self._k
        rotation, position = pose[:, :3, :3], pose[:, :3, 3]
        theta = np.empty((len(rotation), 2, 2, 2, 6))  # (pose, shoulder, elbow, wrist, axis)
        p5 = position - k.d6 * rotation[:, :, 2]
        phi = np.arctan2(p5[:, 1], p5[:, 0])
        spread = acos_clipped(k.d4 / np.hypot(p5[:, 0], p5[:, 1]))
        t1 = (phi + k.quarter_turn)[:, None] + spread[:, None] * _PLUS_MINUS  # (n, shoulder)
        c1, s1 = np.cos(t1), np.sin(t1)
        # z1 = (s1, -c1, 0): axis of joints 2, 3, 4; its components in the flange frame are (s5 c6, -s5 s6, c5)
        z1 = np.empty((*t1.shape, 3))
        z1[..., 0] = s1
        np.negative(c1, out=z1[..., 1])
        z1[..., 2] = 0.0
        axes = np.swapaxes(rotation, -1, -2)[:, None]  # the flange's x (n), y (o), z axes as rows
        n1, o1, z61 = np.moveaxis(np.add.reduce(z1[..., None, :] * axes, axis=-1), -1, 0)  # (n, shoulder) each
        sin5 = np.hypot(n1, o1)
        t5 = np.arctan2(sin5, z61)[..., None, None] * _PLUS_MINUS  # (n, shoulder, 1, wrist)
        singular = (sin5 < WRIST_SINGULAR)[..., None, None]
        t6 = np.arctan2(o1[..., None, None] * _MINUS_PLUS, n1[..., None, None] * _PLUS_MINUS)
        np.copyto(t6, 0.0, where=singular)
        c1, s1 = c1[..., None, None], s1[..., None, None]
        t3_up = self._arm(c1, s1, t5, t6, axes[:, :, None, None], p5, theta)
        stuck = singular & np.isnan(t3_up)  # q6 = 0 leaves joint 4 out of the arm's reach
        if stuck.any():
            t6_reach = self._singular_q6(t1[..., None, None], t5, axes[:, :, None, None, 0], p5[:, None, None, None])
            redo = np.empty_like(theta)
            self._arm(c1, s1, t5, t6_reach, axes[:, :, None, None], p5, redo)
            np.copyto(theta[..., 1:4], redo[..., 1:4], where=stuck[..., None])
            t6 = np.where(stuck, t6_reach, t6)
        theta[..., 0] = t1[..., None, None]
        theta[..., 4] = t5
        theta[..., 5] = t6
        return theta

    def _arm(self, c1, s1, t5, t6, axes, p5, theta) -> np.ndarray:
        """(q2, q3, q4) into theta[..., 1:4] (n, shoulder, elbow, wrist) from cos and sin of q1 and from q5, q6
        (n, shoulder, 1, wrist); returns acos of the elbow, NaN where out of reach."""
        k = self._k
        n, o, z6 = axes[..., 0, :], axes[..., 1, :], axes[..., 2, :]
        c5, s5, c6, s6 = np.cos(t5), np.sin(t5), np.cos(t6), np.sin(t6)
        # frame 4 = flange . Rz(-q6) Rx(90) Rz(-q5): its x and z axes, and its origin
        z4 = -s6[..., None] * n - c6[..., None] * o
        x4 = (c5 * c6)[..., None] * n - (c5 * s6)[..., None] * o - s5[..., None] * z6
        p4 = p5[:, None, None, None] - k.d5 * z4
        # in the frame of joint 1 (Rz(q1) Rx(90) at height d1): the planar arm of joints 2 and 3
        px = c1 * p4[..., 0] + s1 * p4[..., 1]
        py = p4[..., 2] - k.d1
        t3_up = acos_clipped((px * px + py * py - k.a2_squared - k.a3_squared) / k.elbow_denominator)
        t3 = np.multiply(t3_up, _PLUS_MINUS[:, None], out=theta[..., 2])  # (n, shoulder, elbow, wrist)
        t2 = np.subtract(np.arctan2(py, px), np.arctan2(k.a3 * np.sin(t3), k.a2 + k.a3 * np.cos(t3)), out=theta[..., 1])
        t234 = np.arctan2(x4[..., 2], c1 * x4[..., 0] + s1 * x4[..., 1])
        np.subtract(t234 - t2, t3, out=theta[..., 3])
        return t3_up

    def _singular_q6(self, t1, t5, n, p5) -> np.ndarray:
        """At the wrist singularity q6 turns the d5 offset about p5 in the arm plane: the q6 that puts joint 4
        at the middle of the 2R arm's reach (or as near it as the d5 circle allows)."""
        c1, s1 = np.cos(t1), np.sin(t1)
        x5, y5 = c1 * p5[..., 0] + s1 * p5[..., 1], p5[..., 2] - self.d1  # p5 in the plane of joint 1's frame
        dist = np.hypot(x5, y5)
        middle = (abs(abs(self.a2) - abs(self.a3)) + abs(self.a2) + abs(self.a3)) / 2.0
        radius = np.clip(middle, dist - self.d5, dist + self.d5)
        turn = np.arccos(np.clip((dist**2 + self.d5**2 - radius**2) / (2.0 * self.d5 * dist), -1.0, 1.0))
        angle = np.arctan2(y5, x5) + turn  # direction of z4 in that plane
        t234 = np.arctan2(np.cos(angle), -np.sin(angle))  # z4 = (sin t234, -cos t234) in the plane
        x1 = np.stack([c1, s1, np.zeros_like(c1)], axis=-1)
        y1 = np.stack([np.zeros_like(c1), np.zeros_like(c1), np.ones_like(c1)], axis=-1)
        z1 = np.stack([s1, -c1, np.zeros_like(c1)], axis=-1)
        x4 = np.cos(t234)[..., None] * x1 + np.sin(t234)[..., None] * y1
        z4 = np.sin(t234)[..., None] * x1 - np.cos(t234)[..., None] * y1
        # column 0 of R46 = Rz(q5) Rx(-90) Rz(q6) is (c5 c6, s5 c6, -s6) = (x4 . n, z1 . n, z4 . n)
        x4n, z1n, z4n = (np.sum(axis * n, axis=-1) for axis in (x4, z1, z4))
        return np.arctan2(-z4n, np.cos(t5) * x4n + np.sin(t5) * z1n)

    def _theta_floats(self, pose: np.ndarray) -> np.ndarray | None:
        """theta (rad) as (n, shoulder, elbow, wrist, axis) of (n, 4, 4) poses, pose by pose on Python floats:
        the formulas of _solve and _arm written out per branch (NaN propagates as in numpy). None where math raises
        instead (an infinite coordinate, p5 on the base z axis) or a pose needs _singular_q6 (q6 = 0 leaves joint 4
        out of reach at the wrist singularity): the batched path then takes the call."""
        f = self._floats
        atan2, cos, sin = math.atan2, math.cos, math.sin
        rows: list[tuple[float, ...]] = []
        try:
            for (nx, ox, zx, px), (ny, oy, zy, py), (nz, oz, zz, pz), _ in pose.tolist():
                p5x, p5y, p5z = px - f.d6 * zx, py - f.d6 * zy, pz - f.d6 * zz
                base = atan2(p5y, p5x) + f.quarter_turn
                spread = acos_clipped_float(f.d4 / math.hypot(p5x, p5y))
                for t1 in (base + spread, base - spread):
                    c1, s1 = cos(t1), sin(t1)
                    # components of n, o, z6 along z1 = (s1, -c1, 0) (0 nz etc.: NaN where nz is infinite)
                    n1, o1 = s1 * nx - c1 * ny + 0.0 * nz, s1 * ox - c1 * oy + 0.0 * oz
                    sin5 = math.hypot(n1, o1)
                    t5_up = atan2(sin5, s1 * zx - c1 * zy + 0.0 * zz)
                    singular = sin5 < WRIST_SINGULAR
                    by_wrist = []
                    for sign in (1.0, -1.0):
                        t5 = t5_up * sign
                        t6 = 0.0 if singular else atan2(-sign * o1, sign * n1)
                        c5, s5, c6, s6 = cos(t5), sin(t5), cos(t6), sin(t6)
                        # frame 4: its z axis, x axis and origin; then the planar arm of joints 2 and 3
                        z4x, z4y, z4z = -s6 * nx - c6 * ox, -s6 * ny - c6 * oy, -s6 * nz - c6 * oz
                        x4x = c5 * c6 * nx - c5 * s6 * ox - s5 * zx
                        x4y = c5 * c6 * ny - c5 * s6 * oy - s5 * zy
                        x4z = c5 * c6 * nz - c5 * s6 * oz - s5 * zz
                        px4 = c1 * (p5x - f.d5 * z4x) + s1 * (p5y - f.d5 * z4y)
                        py4 = p5z - f.d5 * z4z - f.d1
                        cos3 = (px4 * px4 + py4 * py4 - f.a2_squared - f.a3_squared) / f.elbow_denominator
                        t3_up = acos_clipped_float(cos3)
                        if singular and math.isnan(t3_up):
                            return None  # q6 = 0 leaves joint 4 out of the arm's reach: _singular_q6
                        reach = atan2(py4, px4)
                        t234 = atan2(x4z, c1 * x4x + s1 * x4y)
                        for t3 in (t3_up, -t3_up):
                            t2 = reach - atan2(f.a3 * sin(t3), f.a2 + f.a3 * cos(t3))
                            by_wrist.append((t1, t2, t3, t234 - t2 - t3, t5, t6))
                    rows += (by_wrist[0], by_wrist[2], by_wrist[1], by_wrist[3])  # elbow, then wrist
        except (ValueError, ZeroDivisionError, OverflowError):
            return None
        return np.array(rows).reshape(len(pose), 2, 2, 2, 6)
