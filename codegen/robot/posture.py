"""The other postures a cell's home could give the arm: the home turned half a turn about axis 1 (the arm facing the
other way), within the joint limits and the cell's joint margin."""

from __future__ import annotations

import numpy as np

from codegen.robot.margins import joint_margins
from codegen.robot.solve import TURN


def turned_homes(arm, home, margin_deg: float) -> list[np.ndarray]:
    """The home with axis 1 half a turn either way (deg), each within axis 1's limits by the margin: from a home that
    faces away from the work, the nearest solution at each pose is the arm reaching back over itself (UR's elbow
    below the shoulder); facing the work it is the elbow above."""
    out = []
    for step in (-TURN / 2, TURN / 2):
        q = np.asarray(home, dtype=float).copy()
        q[0] += step
        if joint_margins(arm, q)[0] >= margin_deg:
            out.append(q)
    return out
