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

import numpy as np

from codegen.robot.kinematics import acos_clipped, nan_incomplete_rows, wrap_deg

ALPHA_DEG = (90, 0, 0, 90, -90, 0)
COS_ALPHA = (0.0, 1.0, 1.0, 0.0, 0.0, 1.0)  # exact, not cos(pi / 2) = 6e-17
SIN_ALPHA = (1.0, 0.0, 0.0, 1.0, -1.0, 0.0)
WRIST_SINGULAR = 1e-12  # |sin q5| below this: q6 only acts together with q2 + q3 + q4 (see URDH)


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

    def _dh(self) -> tuple[tuple[float, ...], tuple[float, ...]]:
        return (0.0, self.a2, self.a3, 0.0, 0.0, 0.0), (self.d1, 0.0, 0.0, self.d4, self.d5, self.d6)

    def _frames(self, joints_deg: np.ndarray, count: int) -> np.ndarray:
        """(..., 4, 4): DH frame `count` in the base frame (0 <= count <= 6)."""
        q = np.radians(np.asarray(joints_deg, dtype=float))
        a, d = self._dh()
        out = np.broadcast_to(np.eye(4), (*q.shape[:-1], 4, 4))
        for i in range(count):
            c, s = np.cos(q[..., i]), np.sin(q[..., i])
            ca, sa = COS_ALPHA[i], SIN_ALPHA[i]
            link = np.zeros((*q.shape[:-1], 4, 4))
            link[..., 0, :] = np.stack([c, -s * ca, s * sa, a[i] * c], axis=-1)
            link[..., 1, :] = np.stack([s, c * ca, -c * sa, a[i] * s], axis=-1)
            link[..., 2, 1:] = (sa, ca, d[i])
            link[..., 3, 3] = 1.0
            out = out @ link
        return out

    def fk(self, joints_deg: np.ndarray) -> np.ndarray:
        """(..., 6) axis values (deg) -> (..., 4, 4) flange2base (mm), base = the controller's base frame."""
        return self._frames(joints_deg, 6)

    def wrist_center(self, joints_deg: np.ndarray) -> np.ndarray:
        """(..., 3) where axes 5 and 6 meet (DH frame 5's origin, flange - d6 z6), base frame, mm."""
        return self._frames(joints_deg, 5)[..., :3, 3]

    def ik(self, flange2base: np.ndarray) -> np.ndarray:
        """(..., 4, 4) flange2base -> (..., 8, 6) axis values (deg, wrapped to (-180, 180]); NaN rows: none."""
        pose = np.asarray(flange2base, dtype=float)
        with np.errstate(invalid="ignore", divide="ignore"):
            theta = self._solve(pose[..., :3, :3], pose[..., :3, 3])  # (..., s, w, e, 6)
        theta = np.swapaxes(theta, -2, -3)  # (..., shoulder, elbow, wrist, 6)
        joints = wrap_deg(np.degrees(theta.reshape(*theta.shape[:-4], 8, 6)))
        return nan_incomplete_rows(joints)

    def _solve(self, rotation: np.ndarray, position: np.ndarray) -> np.ndarray:
        n, o, z6 = (rotation[..., None, None, :, i] for i in range(3))  # broadcast over (shoulder, wrist)
        p5 = position - self.d6 * rotation[..., :, 2]
        phi = np.arctan2(p5[..., 1], p5[..., 0])
        spread = acos_clipped(self.d4 / np.hypot(p5[..., 0], p5[..., 1]))
        t1 = np.stack([phi + math.pi / 2 + spread, phi + math.pi / 2 - spread], axis=-1)[..., None]  # (..., 2, 1)
        # z1 = (s1, -c1, 0): axis of joints 2, 3, 4; its components in the flange frame are (s5 c6, -s5 s6, c5)
        z1 = np.stack([np.sin(t1), -np.cos(t1), np.zeros_like(t1)], axis=-1)
        n1, o1 = np.sum(n * z1, axis=-1), np.sum(o * z1, axis=-1)
        sin5 = np.hypot(n1, o1)
        t5_up = np.arctan2(sin5, np.sum(z6 * z1, axis=-1))
        t5 = np.concatenate([t5_up, -t5_up], axis=-1)  # (..., 2 shoulder, 2 wrist)
        t1 = np.broadcast_to(t1, t5.shape)
        sign5 = np.where(np.arange(2) == 0, 1.0, -1.0)
        singular = np.broadcast_to(sin5, t5.shape) < WRIST_SINGULAR
        t6 = np.where(singular, 0.0, np.arctan2(-sign5 * o1, sign5 * n1))
        arm = self._arm(t1, t5, t6, n, o, z6, position[..., None, None, :])
        stuck = singular & np.isnan(arm).all(axis=(-2, -1))  # q6 = 0 leaves joint 4 out of the arm's reach
        if stuck.any():
            t6_reach = self._singular_q6(t1, t5, n, p5[..., None, None, :])
            redo = self._arm(t1, t5, t6_reach, n, o, z6, position[..., None, None, :])
            arm = np.where(stuck[..., None, None], redo, arm)
            t6 = np.where(stuck, t6_reach, t6)
        t2, t3, t4 = arm[..., 0, :], arm[..., 1, :], arm[..., 2, :]
        parts = [t1[..., None], t2, t3, t4, t5[..., None], t6[..., None]]
        return np.stack([np.broadcast_to(x, t3.shape) for x in parts], axis=-1)

    def _arm(self, t1, t5, t6, n, o, z6, position) -> np.ndarray:
        """(q2, q3, q4) x (elbow 0, 1) as (..., 2, 2, 3, 2) from q1, q5, q6 (rad)."""
        c1, s1 = np.cos(t1), np.sin(t1)
        c5, s5, c6, s6 = np.cos(t5), np.sin(t5), np.cos(t6), np.sin(t6)
        # frame 4 = flange . Rz(-q6) Rx(90) Rz(-q5): its x and z axes, and its origin
        z4 = -s6[..., None] * n - c6[..., None] * o
        x4 = (c5 * c6)[..., None] * n - (c5 * s6)[..., None] * o - s5[..., None] * z6
        p4 = position - self.d6 * z6 - self.d5 * z4
        # in the frame of joint 1 (Rz(q1) Rx(90) at height d1): the planar arm of joints 2 and 3
        px = c1 * p4[..., 0] + s1 * p4[..., 1]
        py = p4[..., 2] - self.d1
        cos3 = (px * px + py * py - self.a2 * self.a2 - self.a3 * self.a3) / (2.0 * self.a2 * self.a3)
        t3_up = acos_clipped(cos3)
        t3 = np.stack([t3_up, -t3_up], axis=-1)  # (..., 2, 2, 2 elbow)
        t2 = np.arctan2(py, px)[..., None] - np.arctan2(self.a3 * np.sin(t3), self.a2 + self.a3 * np.cos(t3))
        t234 = np.arctan2(x4[..., 2], c1 * x4[..., 0] + s1 * x4[..., 1])
        return np.stack([t2, t3, t234[..., None] - t2 - t3], axis=-2)

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
