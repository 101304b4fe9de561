"""Ortho-parallel 6R arms with a spherical wrist (ABB, KUKA): closed-form, batched forward and inverse kinematics."""

# Geometry and formulas: M. Brandstoetter, A. Angerer, M. Hofbaur, "An Analytical Solution of the Inverse
# Kinematics Problem of Industrial Serial Manipulators with an Ortho-parallel Basis and a Spherical Wrist",
# Austrian Robotics Workshop 2014 (forward kinematics: wrist centre c and orientation R0e = R0c(theta1..3) .
# Rce(theta4..6); inverse: theta1 (2 solutions), theta2/theta3 (2 per theta1), wrist (2 per arm solution)).

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from types import SimpleNamespace

import numpy as np

from codegen.robot.kinematics import (
    ROT_Z,
    SMALL_BATCH,
    ZY_FACTORS,
    acos_clipped,
    acos_clipped_float,
    finish_ik,
    in_chunks,
    sqrt_clipped,
    sqrt_clipped_float,
    trig_table,
    wrap_deg,
)

SHOULDER_SINGULAR_MM = 1e-10  # wrist centre this close to axis 1 (b = 0): theta1 is free, q1 = 0 is chosen
WRIST_SINGULAR = 1e-12  # |sin theta5| below this: theta4 and theta6 only act as a sum, q4 = 0 is chosen

# The batched code keeps numpy calls few (a call costs about as much for 1 pose as for 100): every per-arm
# constant is a cached numpy scalar, rotations are gathered from trig_table, and ik works on one array
# theta (axis, wrist, shoulder, pose, elbow) whose branch axes broadcast, written in place.
_FK_FACTORS = np.stack(  # trig_table entries of (angles, 5) flattened, multiplied pairwise: R0c, Rz Ry, Rz
    [ZY_FACTORS + 5 * np.array([[0], [6]]), ZY_FACTORS + 5 * np.array([[3], [4]]), [ROT_Z + 25, np.full(9, 28)]]
)
_IK_FACTORS = np.stack([ZY_FACTORS + 5 * np.array([[0], [1]]), ZY_FACTORS + 5 * np.array([[0], [2]])])  # R0c
_RCE_ENTRIES = np.array([5, 5, 2, 8, 0, 3, 6])  # Rce flattened: r12, (sin5 goes here), r02, r22, r00, r10, r20
_BACK_TURN = np.array([[0.0], [math.pi]])  # (shoulder, 1): theta1 front, back = + 180 deg
_LATERAL_SIGN = np.array([[-1.0], [1.0]])  # theta1 = phi - lateral (front), phi + lateral - 180 (back)
_GAMMA_SIGN = np.array([[1.0], [-1.0]])  # (shoulder, 1)
_ELBOW_SIGN = np.array([1.0, -1.0])  # (elbow): beta, -beta
_OVER_SIGN = np.array([1.0, -1.0, 1.0])[:, None, None, None]  # wrist 1: theta4 + 180, -theta5, theta6 + 180
_OVER_TURN = np.array([math.pi, 0.0, math.pi])[:, None, None, None]


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
    def _k(self) -> SimpleNamespace:
        """Per-arm constants of fk and ik, as numpy scalars and arrays (the same values the formulas need)."""
        signs = np.asarray(self.signs, dtype=float)
        offsets = np.asarray(self.offsets_deg, dtype=float)
        k2 = self.a2 * self.a2 + self.c3 * self.c3
        k = math.sqrt(k2)
        return SimpleNamespace(
            signs=signs,
            offsets=offsets,
            to_joints_scale=signs * (180.0 / math.pi),  # signs * degrees(theta): degrees is theta * (180 / pi)
            to_joints_shift=signs * offsets,
            plane_base=np.array([self.a1, self.c1]),  # (x, z) of axis 2 in the arm plane
            plane_k=np.array(math.hypot(self.a2, self.c3)),
            psi3=np.array(self.psi3),
            a1=np.array(self.a1),
            b=np.array(self.b),
            c1=np.array(self.c1),
            c2=np.array(self.c2),
            c4=np.array(self.c4),
            k=np.array(k),
            reach_shift=np.array([[0.0], [2.0 * self.a1]]),  # wrist centre's distance from axis 2: front, back
            c2_squared=np.array(self.c2 * self.c2),
            k2=np.array(k2),
            elbow_denominator=np.array(2.0 * self.c2 * k),
            q1_zero=np.array(math.radians(self.offsets_deg[0])),
            q4_zero=np.array(math.radians(self.offsets_deg[3])),
        )

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
        return np.radians(self._k.signs * q + self._k.offsets)

    def _joints(self, theta: np.ndarray) -> np.ndarray:
        return wrap_deg(self._k.signs * (np.degrees(theta) - self._k.offsets))

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

    def sides_one(self, q: list[float]) -> tuple[float, float]:
        """wrist_x_axis1 and elbow_side of one pose's axis values (deg) on Python floats, by the same operations
        (radians is x * (pi / 180) in numpy too)."""
        to_rad = math.pi / 180.0
        t2 = (self.signs[1] * q[1] + self.offsets_deg[1]) * to_rad
        t3 = (self.signs[2] * q[2] + self.offsets_deg[2]) * to_rad
        x = self.a1 + self.c2 * math.sin(t2) + math.hypot(self.a2, self.c3) * math.sin(t2 + t3 + self.psi3)
        return x, math.sin(t3 + self.psi3)

    def elbow_side(self, joints_deg: np.ndarray) -> np.ndarray:
        """sin(theta3 + psi3): > 0 when the wrist centre is in front of the lower arm (axis 2 - axis 3)."""
        t = self.theta(joints_deg)
        return np.sin(t[..., 2] + self.psi3)

    def link_frames(self, joints_deg: np.ndarray) -> np.ndarray:
        """(..., 7, 4, 4): a frame per link in the base frame, mm, each parallel to the base frame at theta = 0:
        0 the base; 1 turned by theta1 about z at the base origin; 2 at axis 2 (a1, b, c1 in frame 1) turned by
        theta2 about y; 3 at axis 3 (c2 up frame 2) turned by theta3 about y; 4, 5, 6 at the wrist centre (a2,
        0, c3 in frame 3) turned by theta4 about z and theta5 about y; 6 the flange (c4 along frame 5's z, turned
        by theta6 about z) (the paper's chain: R0c = Rz(theta1) Ry(theta2 + theta3), Rce = Rz Ry Rz)."""
        t = self.theta(joints_deg)
        steps = (
            (0, (0.0, 0.0, 0.0)),
            (1, (self.a1, self.b, self.c1)),
            (1, (0.0, 0.0, self.c2)),
            (0, (self.a2, 0.0, self.c3)),
            (1, (0.0, 0.0, 0.0)),
            (0, (0.0, 0.0, self.c4)),  # Tz(c4) Rz(theta6) = Rz(theta6) Tz(c4): frame 6 is the flange
        )  # per joint: the axis it turns about (0: z, 1: y) and its origin in the frame before it
        out = np.empty((*t.shape[:-1], 7, 4, 4))
        out[..., 0, :, :] = np.eye(4)
        for i, (axis, origin) in enumerate(steps):
            c, s = np.cos(t[..., i]), np.sin(t[..., i])
            link = np.zeros((*t.shape[:-1], 4, 4))
            if axis == 0:
                link[..., 0, 0], link[..., 0, 1], link[..., 1, 0], link[..., 1, 1], link[..., 2, 2] = c, -s, s, c, 1.0
            else:
                link[..., 0, 0], link[..., 0, 2], link[..., 2, 0], link[..., 2, 2], link[..., 1, 1] = c, s, -s, c, 1.0
            link[..., :3, 3] = origin
            link[..., 3, 3] = 1.0
            out[..., i + 1, :, :] = out[..., i, :, :] @ link
        return out

    def fk(self, joints_deg: np.ndarray) -> np.ndarray:
        """(..., 6) axis values (deg) -> (..., 4, 4) flange2base (mm)."""
        q = np.asarray(joints_deg, dtype=float)
        return in_chunks(self._fk, q.reshape(-1, 6), (4, 4)).reshape(*q.shape[:-1], 4, 4)

    def _fk(self, q: np.ndarray) -> np.ndarray:
        """fk of (n, 6) axis values, batched."""
        k = self._k
        # theta1..6, theta2 + theta3, theta2 + theta3 + psi3 (as theta and _arm_plane compute them)
        angles = np.empty((len(q), 8))
        t = np.multiply(k.signs, q, out=angles[:, :6])
        np.add(t, k.offsets, out=t)
        np.radians(t, out=t)
        np.add(t[:, 1], t[:, 2], out=angles[:, 6])
        np.add(angles[:, 6], k.psi3, out=angles[:, 7])
        table = trig_table(angles)
        factors = table.reshape(len(q), 40)[:, _FK_FACTORS]
        rotations = (factors[:, :, 0] * factors[:, :, 1]).reshape(len(q), 3, 3, 3)  # R0c, Rz4 Ry5, Rz6
        out = np.zeros((len(q), 4, 4))
        rotation = np.matmul(rotations[:, 0], rotations[:, 1] @ rotations[:, 2], out=out[:, :3, :3])  # R0c Rce
        # the wrist centre (as wrist_center): x, z in the arm plane, turned by theta1
        plane = k.plane_base + k.c2 * table[:, 1, 1::-1] + k.plane_k * table[:, 7, 1::-1]
        out[:, :2, 3] = plane[:, :1] * table[:, 0, :2] + k.b * table[:, 0, 2::-2]  # x (c, s) + b (-s, c)
        out[:, 2, 3] = plane[:, 1]
        out[:, :3, 3] += k.c4 * rotation[:, :, 2]
        out[:, 3, 3] = 1.0
        return out

    def ik(self, flange2base: np.ndarray, batched: bool | None = None) -> np.ndarray:
        """(..., 4, 4) flange2base -> (..., 8, 6) axis values (deg, wrapped to (-180, 180]); NaN rows: none.
        batched: numpy's path (True) or pose by pose (False); None: by the number of poses."""
        pose = np.asarray(flange2base, dtype=float)
        return self._ik(pose, scalar=pose.size <= 16 * SMALL_BATCH if batched is None else not batched)

    def _ik(self, pose: np.ndarray, scalar: bool) -> np.ndarray:
        """ik pose by pose on Python floats (scalar; unless math refuses a pose) or batched in numpy."""
        batch = pose.shape[:-2]
        pose = pose.reshape(-1, 4, 4)
        theta = self._theta_floats(pose) if scalar else None
        if theta is None:
            with np.errstate(invalid="ignore", divide="ignore"):
                theta = in_chunks(self._theta, pose, (2, 2, 2, 6))
        # signs * (degrees(theta) - offsets), exactly (signs +-1)
        joints = np.multiply(theta, self._k.to_joints_scale, out=np.empty((len(pose), 2, 2, 2, 6)))
        joints -= self._k.to_joints_shift
        return finish_ik(joints).reshape(*batch, 8, 6)

    def _theta(self, pose: np.ndarray) -> np.ndarray:
        """theta (rad) of (n, 4, 4) poses as (n, shoulder, elbow, wrist, axis), batched."""
        theta = np.empty((6, 2, 2, len(pose), 2))  # (axis, wrist, shoulder, pose, elbow)
        self._arm(pose[:, :3, 3].T - self._k.c4 * pose[:, :3, 2].T, theta)
        self._wrist(pose[:, :3, :3], theta)
        return theta.transpose(3, 2, 4, 1, 0)  # (pose, shoulder, elbow, wrist, axis): the branch order

    def _arm(self, center: np.ndarray, theta: np.ndarray) -> None:
        """theta1..3 into theta[0:3] from the wrist centres (3, n)."""
        k = self._k
        cx, cy, cz = center
        r2 = cx * cx + cy * cy
        phi = np.arctan2(cy, cx)
        if self.b == 0.0:
            rho = np.sqrt(r2)  # the wrist centre's distance from axis 1 in the arm plane (sqrt_clipped(r2 - 0))
            np.copyto(phi, k.q1_zero, where=r2 < SHOULDER_SINGULAR_MM**2)  # on axis 1 any theta1: choose q1 = 0
            theta1 = phi  # (the lateral angle atan2(b, rho) is 0)
        else:
            rho = sqrt_clipped(r2 - self.b * self.b)
            theta1 = phi + np.arctan2(self.b, rho) * _LATERAL_SIGN  # (shoulder, n)
        np.subtract(theta1[..., None], _BACK_TURN[..., None], out=theta[0])
        height = cz - k.c1
        nx = (rho - k.a1) + k.reach_shift  # (shoulder, n)
        s_2 = nx * nx + height * height
        beta = acos_clipped((s_2 - k.c2_squared - k.k2) / k.elbow_denominator)  # elbow angle theta3 + psi3
        beta = beta[..., None] * _ELBOW_SIGN  # (shoulder, n, elbow)
        # direction of the wrist centre seen from axis 2 (from vertical, towards the arm plane's x)
        gamma = np.arctan2(nx, height) * _GAMMA_SIGN
        # theta2 from the elbow angle itself (the paper's acos of the shoulder triangle, written as the angle of
        # c2 + k e^(i beta)): lower arm and forearm then reach the wrist centre also where acos is ill-conditioned
        shoulder = np.arctan2(k.k * np.sin(beta), k.c2 + k.k * np.cos(beta))
        np.subtract(gamma[..., None], shoulder, out=theta[1])
        np.subtract(beta, k.psi3, out=theta[2])

    def _wrist(self, flange_rotation: np.ndarray, theta: np.ndarray) -> None:
        """theta4..6 into theta[3:6] from theta1..3 and the flange rotations (n, 3, 3); wrist 1 is wrist 0
        turned over (theta4 + 180, -theta5, theta6 + 180)."""
        up = theta[:, 0]  # (axis, shoulder, n, elbow)
        angles = np.empty((*up.shape[1:3], 3))  # theta1, theta2 + theta3 of elbow 0 and 1
        angles[..., 0] = up[0, :, :, 0]
        np.add(up[1], up[2], out=angles[..., 1:])
        factors = trig_table(angles).reshape(*angles.shape[:2], 15)[..., _IK_FACTORS]
        arm2base = (factors[..., 0, :] * factors[..., 1, :]).reshape(*up.shape[1:], 3, 3)  # R0c
        wrist2arm = np.swapaxes(arm2base, -1, -2) @ flange_rotation[:, None]  # Rce, (shoulder, n, elbow, 3, 3)
        rce = wrist2arm.reshape(-1, 9).T[_RCE_ENTRIES].reshape(7, *up.shape[1:])
        sin5, r20 = rce[1], rce[6]
        np.hypot(rce[2], rce[0], out=sin5)  # hypot(r02, r12)
        t4 = np.arctan2(rce[0:2], rce[2:4], out=up[3:5])[0]  # atan2(r12, r02), atan2(sin5, r22)
        np.copyto(t4, self._k.q4_zero, where=sin5 < WRIST_SINGULAR)  # wrist singularity: q4 = 0
        trig = np.empty((3, *up.shape[1:]))
        c5 = np.cos(up[3:5], out=trig[0:2])[1]
        np.sin(t4, out=trig[2])
        # Rz(-theta4) Rce = Ry(theta5) Rz(theta6): its column 0 is (c5 c6, s6, -s5 c6), exact also when sin5 = 0;
        # a00 = c4 r00 + s4 r10, a10 = -s4 r00 + c4 r10 from the products (c4, s4) x (r00, r10)
        products = trig[0::2, None] * rce[4:6]
        a00 = products[0, 0] + products[1, 1]
        a10 = products[0, 1] - products[1, 0]
        np.arctan2(a10, c5 * a00 - sin5 * r20, out=up[5])
        np.add(up[3:6] * _OVER_SIGN, _OVER_TURN, out=theta[3:6, 1])

    @cached_property
    def _floats(self) -> SimpleNamespace:
        """_k as Python floats, for the pose-by-pose path."""
        return SimpleNamespace(**{name: value.item() for name, value in vars(self._k).items() if value.ndim == 0})

    def _theta_floats(self, pose: np.ndarray) -> np.ndarray | None:
        """theta (rad) as (n, shoulder, elbow, wrist, axis) of (n, 4, 4) poses, pose by pose on Python floats:
        the formulas of _arm and _wrist written out per branch (Rce as sums instead of a matrix product; NaN
        propagates as in numpy). None where math raises instead (an infinite coordinate): the batched path then
        takes the call."""
        f = self._floats
        b, pi, atan2, cos, sin = self.b, math.pi, math.atan2, math.cos, math.sin
        rows: list[tuple[float, ...]] = []
        try:
            for (r00, _, r02, px), (r10, _, r12, py), (r20, _, r22, pz), _ in pose.tolist():
                cx, cy, height = px - f.c4 * r02, py - f.c4 * r12, pz - f.c4 * r22 - f.c1
                r2 = cx * cx + cy * cy
                phi = atan2(cy, cx)
                if b == 0.0:
                    rho = math.sqrt(r2)
                    if r2 < SHOULDER_SINGULAR_MM**2:
                        phi = f.q1_zero
                    shoulders = ((phi, rho - f.a1, 1.0), (phi - pi, rho - f.a1 + 2.0 * self.a1, -1.0))
                else:
                    rho = sqrt_clipped_float(r2 - b * b)
                    lateral = atan2(b, rho)
                    shoulders = (
                        (phi - lateral, rho - f.a1, 1.0),
                        (phi + lateral - pi, rho - f.a1 + 2.0 * self.a1, -1.0),
                    )
                for t1, nx, gamma_sign in shoulders:
                    beta = acos_clipped_float((nx * nx + height * height - f.c2_squared - f.k2) / f.elbow_denominator)
                    gamma = atan2(nx, height) * gamma_sign
                    c1, s1 = cos(t1), sin(t1)
                    for elbow in (beta, -beta):
                        t2 = gamma - atan2(f.k * sin(elbow), f.c2 + f.k * cos(elbow))
                        t3 = elbow - f.psi3
                        c, s = cos(t2 + t3), sin(t2 + t3)
                        # Rce = R0c^T R, R0c = [[c1 c, -s1, c1 s], [s1 c, c1, s1 s], [-s, 0, c]]: columns 0, 2
                        # (0 r20, 0 r22 as in the matrix product: NaN where r20, r22 are infinite)
                        w00 = c1 * c * r00 + s1 * c * r10 - s * r20
                        w10 = -s1 * r00 + c1 * r10 + 0.0 * r20
                        w20 = c1 * s * r00 + s1 * s * r10 + c * r20
                        w02 = c1 * c * r02 + s1 * c * r12 - s * r22
                        w12 = -s1 * r02 + c1 * r12 + 0.0 * r22
                        w22 = c1 * s * r02 + s1 * s * r12 + c * r22
                        sin5 = math.hypot(w02, w12)
                        t4 = f.q4_zero if sin5 < WRIST_SINGULAR else atan2(w12, w02)
                        t5 = atan2(sin5, w22)
                        c4, s4 = cos(t4), sin(t4)
                        t6 = atan2(c4 * w10 - s4 * w00, cos(t5) * (c4 * w00 + s4 * w10) - sin5 * w20)
                        rows.append((t1, t2, t3, t4, t5, t6))
                        rows.append((t1, t2, t3, t4 + pi, -t5, t6 + pi))
        except (ValueError, ZeroDivisionError, OverflowError):
            return None
        return np.array(rows).reshape(len(pose), 2, 2, 2, 6)
