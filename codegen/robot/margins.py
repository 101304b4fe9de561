"""An arm's margins, the one rule every reach proof, generate's and verify's figures and the home check use: each
axis's distance from its joint limits, and the wrist's from its singularity."""

from __future__ import annotations

import numpy as np


def wrist_angle(arm, joints: np.ndarray) -> np.ndarray:
    """The wrist axis in the kinematic model (0 and +-180 deg are singular): OPW theta5, UR's q5."""
    kin = arm.kin
    if arm.family == "opw":
        return kin.signs[4] * joints[..., 4] + kin.offsets_deg[4]
    return joints[..., 4]


def singular_distance(angle: np.ndarray) -> np.ndarray:
    """Degrees from the nearest multiple of 180 deg."""
    r = np.mod(angle, 180.0)
    return np.minimum(r, 180.0 - r)


def joint_margins(arm, joints) -> np.ndarray:
    """Degrees from each axis to its nearer joint limit, for (..., 6) joints (negative: beyond it)."""
    joints = np.asarray(joints, dtype=float)
    return np.minimum(joints - arm.limits[:, 0], arm.limits[:, 1] - joints)


def least_joint_margin(arm, joints) -> tuple[float, tuple[int, ...]]:
    """The least of joint_margins and where it is: the index into joints (..., axis), the axis 0-based last."""
    per_axis = joint_margins(arm, joints)
    where = np.unravel_index(int(np.argmin(per_axis)), per_axis.shape)
    return float(per_axis[where]), tuple(int(i) for i in where)
