"""The page's drawing vocabulary (frames, boxes, lines, points, each with a colour role) and the arm's description."""

from __future__ import annotations

import numpy as np

POSE_DECIMALS = 6  # a 4x4's entries in the page: 1e-6 of a unit vector, 1e-6 mm
FRAME_MM = 60.0  # a taught pose's axes, drawn this long
SLAB_MM = 20.0  # a bench's, a platform's, a belt's and a table's thickness as drawn (the cell gives none)
ROLES = (  # the colour roles the page knows (codegen/view/static/viewer.js PALETTE)
    "frame",
    "mark",
    "taught",
    "bench",
    "wood",
    "box",
    "label",
    "sheet",
    "pick",
    "belt",
    "window",
    "camera",
    "place",
    "beam",
    "sensor",
    "solid",
)


def flat(matrix) -> list[float]:
    """A 4x4 as 16 numbers, row after row, rounded for the page."""
    return [round(float(v), POSE_DECIMALS) for v in np.asarray(matrix, dtype=float).reshape(16)]


def xyz(point) -> list[float]:
    return [round(float(v), POSE_DECIMALS) for v in np.asarray(point, dtype=float)[:3]]


def frame(pose, label: str, role: str = "frame", size: float = FRAME_MM) -> dict:
    """A pose drawn as its three axes (x red, y green, z blue) and a dot of the role's colour at its origin."""
    return {"type": "frame", "pose": flat(pose), "label": label, "role": role, "size": size}


def box(centre2base, size, role: str, label: str = "", opacity: float = 1.0) -> dict:
    """A box: its centre's pose (4x4, mm) and its edge lengths along that pose's x, y, z."""
    out = {"type": "box", "pose": flat(centre2base), "size": [float(s) for s in size], "role": role, "label": label}
    if opacity < 1.0:
        out["opacity"] = opacity
    return out


def cylinder(centre2base, radius: float, length: float, role: str, label: str = "", opacity: float = 1.0) -> dict:
    """A cylinder: its centre's pose (4x4, mm), its radius and its length along that pose's z."""
    out = {"type": "cylinder", "pose": flat(centre2base), "radius": float(radius), "length": float(length),
           "role": role, "label": label}
    if opacity < 1.0:
        out["opacity"] = opacity
    return out


def line(points, role: str, label: str = "", dashed: bool = False) -> dict:
    return {"type": "line", "points": [xyz(p) for p in points], "role": role, "label": label, "dashed": dashed}


def point(position, role: str, label: str = "") -> dict:
    return {"type": "point", "position": xyz(position), "role": role, "label": label}


def translated(pose, offset) -> np.ndarray:
    """The pose moved along its own axes by offset (mm)."""
    out = np.array(pose, dtype=float)
    out[:3, 3] = out[:3, :3] @ np.asarray(offset, dtype=float) + out[:3, 3]
    return out


def arm_description(arm, tcp2flange) -> dict:
    """What the page needs to draw an arm from its catalogue kinematics: the family's parameters (mm, and for an
    ortho-parallel arm the offsets and signs that turn axis values into the paper's angles), the limits and the
    tool. The page's forward kinematics (viewer.js) follow codegen/robot/urdh.py and opw.py; the tests hold them to
    those modules' fk and wrist_center."""
    kin = arm.kin
    if arm.family == "ur":
        params = {k: getattr(kin, k) for k in ("d1", "a2", "a3", "d4", "d5", "d6")}
    else:
        params = {k: getattr(kin, k) for k in ("a1", "a2", "b", "c1", "c2", "c3", "c4")}
        params["offsets_deg"] = list(kin.offsets_deg)
        params["signs"] = list(kin.signs)
    return {
        "model": arm.model,
        "family": arm.family,
        "params": params,
        "limits_deg": [list(pair) for pair in arm.limits_deg],
        "tcp2flange": flat(tcp2flange),
    }
