"""The wrist's distance from its singularity: the one rule every reach proof and verify's figures use."""

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
