"""Ortho-parallel 6R arms with a spherical wrist (ABB, KUKA): closed-form, batched forward and inverse kinematics."""

# Geometry and formulas: M. Brandstoetter, A. Angerer, M. Hofbaur, "An Analytical Solution of the Inverse
# Kinematics Problem of Industrial Serial Manipulators with an Ortho-parallel Basis and a Spherical Wrist",
# Austrian Robotics Workshop 2014 (forward kinematics: wrist centre c and orientation R0e = R0c(theta1..3) .
# Rce(theta4..6); inverse: theta1 (2 solutions), theta2/theta3 (2 per theta1), wrist (2 per arm solution)).

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from codegen.robot.kinematics import (
    ROT_Z,
    acos_clipped,
    nan_incomplete_rows,
    rot_zy,
    sqrt_clipped,
    trig_table,
    wrap_deg,
)

SHOULDER_SINGULAR_MM = 1e-10  # wrist centre this close to axis 1 (b = 0): theta1 is free, q1 = 0 is chosen
WRIST_SINGULAR = 1e-12  # |sin theta5| below this: theta4 and theta6 only act as a sum, q4 = 0 is chosen

# ik works on flat batches with the branch bits as axes: (n, shoulder, elbow) for the arm, wrist last
_LATERAL_SIGN = np.array([-1.0, 1.0])  # theta1 = phi - lateral (front), phi + lateral - pi (back)
_BACK_TURN = np.array([0.0, math.pi])
_GAMMA_SIGN = np.array([1.0, -1.0])  # front, back
_ELBOW_SIGN = np.array([1.0, -1.0])  # beta, -beta
_NEGATE_FIRST = np.array([-1.0, 1.0])
_RCE_USED = np.array([2, 5, 8, 0, 3, 6])  # flat indices of Rce's entries r02, r12, r22, r00, r10, r20


@dataclass(frozen=True)
class OPW:
    """An ortho-parallel arm with a spherical wrist, by the paper's seven lengths (mm).

    Joint mapping: theta_i = signs[i] * q_i + offsets_deg[i], with q_i the controller's axis value and
    theta_i the paper's angle (theta = 0: upper arm, forearm and flange pointing straight up). The offsets
    quoted with the paper's worked examples and used by the opw_kinematics library belong to theta = s * q -
    off: their KUKA (0, -90, 0, 0, 0, 0) and ABB (0, 0, -90, 0, 0, 0) are (0, 90, 0, 0, 0, 0) and (0, 0, 90,
    0, 0, 0) here (checked against the vendors' joint origins); the signs are the same (KUKA (-1, 1, 1, -1,
    1, -1), ABB all +1).

    The flange frame is the paper's end-effector frame: z along axis 6 out of the flange, and at theta = 0
    parallel to the base frame (KUKA's $FLANGE; ABB's tool0 as ROS-Industrial's newer ABB models place it).

    ik branch order (fixed), index = 4 * shoulder + 2 * elbow + wrist:
      shoulder 0: wrist centre in front of axis 1 (x >= 0 in the axis-1 frame, the arm plane theta1 sets),
               1: behind it (reaching over the shoulder, theta1 + 180 deg);
      elbow    0: wrist centre in front of the line axis 2 - axis 3 (the lower arm), sin(theta3 + psi3) >= 0
                  with psi3 = atan2(a2, c3) (the elbow on the usual side),
               1: behind it;
      wrist    0: theta5 >= 0, 1: theta5 < 0 (the same wrist turned over: theta4 + 180, -theta5, theta6 + 180).
    For ABB arms (all signs +1) the index is the confdata cfx of the solution, for KUKA arms (signs[4] = +1)
    shoulder is Status bit 0, wrist Status bit 2 and elbow the complement of Status bit 1.

    Singularities (finite answers where the pose is reachable):
      wrist (theta5 = 0 or 180): only theta4 + theta6 (or their difference) is fixed; branch wrist 0 keeps
        q4 = 0, its wrist-1 twin has theta4 + 180;
      shoulder (b = 0, wrist centre on axis 1): theta1 is free; q1 = 0 is chosen for shoulder 0 (q1 of
        shoulder 1 is 180 deg away);
      elbow (arm stretched or folded): cos values up to 1 + 1e-12 are taken as 1, both elbow rows equal.
    """

    a1: float
    a2: float
    b: float
    c1: float
    c2: float
    c3: float
    c4: float
    offsets_deg: tuple[float, float, float, float, float, float] = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    signs: tuple[int, int, int, int, int, int] = (1, 1, 1, 1, 1, 1)

    @cached_property
    def psi3(self) -> float:
        """atan2(a2, c3) (rad): the forearm's kink, theta3 = -psi3 stretches the arm."""
        return math.atan2(self.a2, self.c3)

    @cached_property
    def _signs(self) -> np.ndarray:
        return np.asarray(self.signs)

    @cached_property
    def _offsets(self) -> np.ndarray:
        return np.asarray(self.offsets_deg, dtype=float)

    @cached_property
    def _to_joints_scale(self) -> np.ndarray:
        return self._signs * (180.0 / math.pi)

    @cached_property
    def _to_joints_shift(self) -> np.ndarray:
        return self._signs * self._offsets

    @cached_property
    def _plane_base(self) -> np.ndarray:
        return np.array([self.a1, self.c1])  # (x, z) of axis 2 in the arm plane

    @property
    def stretched_q3_deg(self) -> float:
        """The controller's axis-3 value at which lower arm and forearm line up (wrist centre farthest)."""
        return self.joints_from_theta_deg(3, -math.degrees(self.psi3))

    def joints_from_theta_deg(self, axis: int, theta_deg: float) -> float:
        """q of one axis (1-based) from the paper's angle, both in deg (not wrapped)."""
        return self.signs[axis - 1] * (theta_deg - self.offsets_deg[axis - 1])

    def theta(self, joints_deg: np.ndarray) -> np.ndarray:
        """The paper's angles (rad), (..., 6), from the controller's axis values (deg)."""
        q = np.asarray(joints_deg, dtype=float)
        return np.radians(self._signs * q + self._offsets)

    def _joints(self, theta: np.ndarray) -> np.ndarray:
        return wrap_deg(self._signs * (np.degrees(theta) - self._offsets))

    def _arm_plane(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Wrist centre in the axis-1 frame: radial x and height z over the base (paper, forward kinematics)."""
        k = math.hypot(self.a2, self.c3)
        x = self.a1 + self.c2 * np.sin(t[..., 1]) + k * np.sin(t[..., 1] + t[..., 2] + self.psi3)
        z = self.c1 + self.c2 * np.cos(t[..., 1]) + k * np.cos(t[..., 1] + t[..., 2] + self.psi3)
        return x, z

    def wrist_center(self, joints_deg: np.ndarray) -> np.ndarray:
        """(..., 3) the wrist centre (axes 4, 5, 6 intersect) in the base frame, mm."""
        t = self.theta(joints_deg)
        x, z = self._arm_plane(t)
        c, s = np.cos(t[..., 0]), np.sin(t[..., 0])
        return np.stack([x * c - self.b * s, x * s + self.b * c, z], axis=-1)

    def wrist_x_axis1(self, joints_deg: np.ndarray) -> np.ndarray:
        """The wrist centre's x in the frame that turns with axis 1 (> 0: in front of axis 1), mm."""
        return self._arm_plane(self.theta(joints_deg))[0]

    def elbow_side(self, joints_deg: np.ndarray) -> np.ndarray:
        """sin(theta3 + psi3): > 0 when the wrist centre is in front of the lower arm (axis 2 - axis 3)."""
        t = self.theta(joints_deg)
        return np.sin(t[..., 2] + self.psi3)

    def fk(self, joints_deg: np.ndarray) -> np.ndarray:
        """(..., 6) axis values (deg) -> (..., 4, 4) flange2base (mm)."""
        t = self.theta(joints_deg)
        batch = t.shape[:-1]
        t = t.reshape(-1, 6)
        # every angle the pose needs, cos and sin taken once: theta1, theta4 | theta2 + theta3, theta5 | theta6 |
        # theta2, theta2 + theta3 + psi3 (the paper's wrist centre in the arm plane)
        angles = np.empty((len(t), 7))
        angles[:, 0:2] = t[:, 0::3]
        np.add(t[:, 1], t[:, 2], out=angles[:, 2])
        angles[:, 3:5] = t[:, 4:6]
        angles[:, 5] = t[:, 1]
        np.add(angles[:, 2], self.psi3, out=angles[:, 6])
        table = trig_table(angles)
        zy = rot_zy(table[:, 0:2], table[:, 2:4])  # R0c = Rz(theta1) Ry(theta2 + theta3), Rz(theta4) Ry(theta5)
        z6 = table[:, 4, ROT_Z].reshape(-1, 3, 3)  # Rz(theta6)
        out = np.zeros((len(t), 4, 4))
        rotation = out[:, :3, :3]
        np.matmul(zy[:, 0], zy[:, 1] @ z6, out=rotation)  # R0c Rce
        # wrist centre (as wrist_center): x, z in the arm plane, turned by theta1 (x c1 - b s1, x s1 + b c1, z)
        plane = self._plane_base + self.c2 * table[:, 5, 1::-1] + math.hypot(self.a2, self.c3) * table[:, 6, 1::-1]
        out[:, :2, 3] = plane[:, 0, None] * table[:, 0, :2] + self.b * table[:, 0, 2::-2]
        out[:, 2, 3] = plane[:, 1]
        out[:, :3, 3] += self.c4 * rotation[:, :, 2]
        out[:, 3, 3] = 1.0
        return out.reshape(*batch, 4, 4)

    def ik(self, flange2base: np.ndarray) -> np.ndarray:
        """(..., 4, 4) flange2base -> (..., 8, 6) axis values (deg, wrapped to (-180, 180]); NaN rows: none."""
        pose = np.asarray(flange2base, dtype=float)
        batch = pose.shape[:-2]
        pose = pose.reshape(-1, 4, 4)
        rotation = pose[:, :3, :3]
        center = pose[:, :3, 3] - self.c4 * rotation[:, :, 2]
        theta = np.empty((len(pose), 2, 2, 2, 6))  # (n, shoulder, elbow, wrist, axis): the branch order
        with np.errstate(invalid="ignore", divide="ignore"):
            self._arm(center, theta)
            self._wrist(rotation, theta)
        # signs * (degrees(theta) - offsets): degrees is theta * (180 / pi), the signs +-1, so this is exact
        joints = theta.reshape(*batch, 8, 6) * self._to_joints_scale - self._to_joints_shift
        return nan_incomplete_rows(wrap_deg(joints))

    def _arm(self, center: np.ndarray, theta: np.ndarray) -> None:
        """theta1..3 of the wrist centres (n, 3) into theta[..., 0:3] (n, shoulder, elbow, wrist, axis)."""
        cx, cy, cz = center[:, 0], center[:, 1], center[:, 2]
        r2 = cx * cx + cy * cy
        phi = np.arctan2(cy, cx)
        if self.b == 0.0:  # theta1 = phi (front), phi - 180 (back); on axis 1 any theta1: choose q1 = 0
            rho = np.sqrt(r2)  # the wrist centre's distance from axis 1 in the arm plane (sqrt_clipped(r2 - 0))
            phi = np.where(r2 < SHOULDER_SINGULAR_MM**2, math.radians(self.offsets_deg[0]), phi)
            t1 = phi[:, None, None, None]  # the lateral angle atan2(b, rho) below is 0
        else:
            rho = sqrt_clipped(r2 - self.b * self.b)
            lateral = np.arctan2(self.b, rho)
            t1 = (phi[:, None] + lateral[:, None] * _LATERAL_SIGN)[..., None, None]
        np.subtract(t1, _BACK_TURN[:, None, None], out=theta[..., 0])  # front, back (over the shoulder)
        height = cz - self.c1
        # radial distance of the wrist centre from axis 2: in front, and reaching over the shoulder
        nx = (rho - self.a1)[:, None] + np.array([0.0, 2.0 * self.a1])
        k2 = self.a2 * self.a2 + self.c3 * self.c3
        k = math.sqrt(k2)
        s_2 = nx * nx + (height * height)[:, None]
        beta = acos_clipped((s_2 - self.c2 * self.c2 - k2) / (2.0 * self.c2 * k))  # elbow angle theta3 + psi3
        beta = beta[..., None] * _ELBOW_SIGN  # (n, shoulder, elbow)
        # direction of the wrist centre seen from axis 2 (from vertical, towards the arm plane's x)
        gamma = np.arctan2(nx, height[:, None]) * _GAMMA_SIGN
        # theta2 from the elbow angle itself (the paper's acos of the shoulder triangle, written as the angle of
        # c2 + k e^(i beta)): lower arm and forearm then reach the wrist centre also where acos is ill-conditioned
        shoulder = np.arctan2(k * np.sin(beta), self.c2 + k * np.cos(beta))
        np.subtract(gamma[..., None, None], shoulder[..., None], out=theta[..., 1])
        np.subtract(beta[..., None], self.psi3, out=theta[..., 2])

    def _wrist(self, flange_rotation: np.ndarray, theta: np.ndarray) -> None:
        """theta4..6 into theta[..., 3:6] from theta1..3 and the flange rotations (n, 3, 3); wrist 1 is wrist 0
        turned over (theta4 + 180, -theta5, theta6 + 180)."""
        up, over = theta[..., 0, :], theta[..., 1, :]  # (n, shoulder, elbow, axis)
        angles = np.empty((len(theta), 2, 3))  # per shoulder: theta1, theta2 + theta3 of elbow 0 and 1
        angles[..., 0] = up[:, :, 0, 0]
        np.add(up[..., 1], up[..., 2], out=angles[..., 1:])
        table = trig_table(angles)
        arm2base = rot_zy(table[:, :, None, 0], table[:, :, 1:])  # R0c, (n, 2, 2, 3, 3)
        wrist2arm = np.swapaxes(arm2base, -1, -2) @ flange_rotation[:, None, None]  # Rce
        # the entries used, each as a contiguous (n, 2, 2) array
        r02, r12, r22, r00, r10, r20 = wrist2arm.reshape(-1, 9).T[_RCE_USED].reshape(6, *angles.shape[:2], 2)
        sin5 = np.hypot(r02, r12)
        t5 = np.arctan2(sin5, r22, out=up[..., 4])
        t4 = np.arctan2(r12, r02, out=up[..., 3])
        np.copyto(t4, math.radians(self.offsets_deg[3]), where=sin5 < WRIST_SINGULAR)  # q4 = 0
        c4, s4, c5 = np.cos(t4), np.sin(t4), np.cos(t5)
        # Rz(-theta4) Rce = Ry(theta5) Rz(theta6): its column 0 is (c5 c6, s6, -s5 c6), exact also when sin5 = 0
        a00 = c4 * r00 + s4 * r10
        a10 = -s4 * r00 + c4 * r10
        t6 = np.arctan2(a10, c5 * a00 - sin5 * r20, out=up[..., 5])
        np.add(t4, math.pi, out=over[..., 3])
        np.negative(t5, out=over[..., 4])
        np.add(t6, math.pi, out=over[..., 5])
