"""The carried box's (or slip sheet's) sweep: no straight segment of its bottom below the tops of the boxes already on
the pallet under it, except on the last descent onto its place (the first ascent off it when unstacking)."""

from __future__ import annotations

import itertools

import numpy as np

from codegen.kinds.pallet.checks import AREA_TOL, _area, _clip
from codegen.kinds.pallet.section import Pallet
from codegen.kinds.pallet.stack import placements
from codegen.poses import rotmat_from_zyx_deg

SAMPLES = 64  # points along each segment (and its two ends)
DEPTH_TOL_MM = 1e-6  # a bottom resting on a top is not below it
PLACE_POSES = ("entry", "approach", "target", "retreat")  # a box's own last descent (first ascent)


def _footprint(tcp2pallet: np.ndarray, tool: np.ndarray, size) -> tuple[np.ndarray, float]:
    """The carried box's footprint (4 x 2, counterclockwise) and its bottom's lowest z, pallet frame."""
    box2pallet = tcp2pallet[:3, :3] @ tool.T  # the box's axes: the tool's at box angle 0
    half = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]]) * np.asarray(size[:2]) / 2
    corners = tcp2pallet[:3, 3] + (half @ box2pallet[:, :2].T) - size[2] * box2pallet[:, 2]
    return corners[:, :2], float(corners[:, 2].min())


def _own(name: str) -> tuple[str, str]:
    """("layer L box N", pose) of a move's name ("layer L sheet", pose: the slip sheet below layer L)."""
    words = name.split()
    if words[2:3] == ["sheet"]:
        return " ".join(words[:3]), " ".join(words[3:])
    return " ".join(words[:-1]), words[-1]


def sweeps(pallet: Pallet, pallet2base: np.ndarray, moves) -> str | None:
    """The first carrying move (ExpectedMove: kind, tcp2base, name, carrying or sheet) whose straight segment from the
    move before it takes the box's (the sheet's) bottom below the top of a box already on the pallet under its
    footprint; None: none. A slip sheet is taken as the pallet's size (the cell gives its thickness alone) and lies
    below its layer's first box."""
    tool = rotmat_from_zyx_deg(*pallet.tool_orientation)
    base2pallet = np.linalg.inv(pallet2base)
    placed = placements(pallet)
    order = {f"layer {p.layer} box {p.number}": i for i, p in enumerate(placed)}
    order |= {f"layer {p.layer} sheet": i for i, p in enumerate(placed) if p.number == 1}
    sheet = (pallet.size[0], pallet.size[1], pallet.slip_thickness)
    shapes = [(p.target[:3, 3], p.box.ccw_deg) for p in placed]
    for before, move in itertools.pairwise(moves):
        held = "sheet" if getattr(move, "sheet", False) else "box" if move.carrying else None
        if held is None:
            continue
        size = sheet if held == "sheet" else pallet.box
        (own_a, pose_a), (own_b, pose_b) = _own(before.name), _own(move.name)
        if own_a == own_b and pose_a in PLACE_POSES and pose_b in PLACE_POSES:
            continue
        mine = order.get(own_b)
        if mine is None:
            continue
        on_pallet = range(mine)  # the boxes placed before it (unstacking: still on the pallet under it)
        a, b = base2pallet @ before.tcp2base, base2pallet @ move.tcp2base
        for t in np.linspace(0.0, 1.0, SAMPLES + 1):
            for rotation in (a[:3, :3], b[:3, :3]):
                here = np.eye(4)
                here[:3, :3], here[:3, 3] = rotation, (1 - t) * a[:3, 3] + t * b[:3, 3]
                foot, bottom = _footprint(here, tool, size)
                for i in on_pallet:
                    top, angle = shapes[i]
                    if bottom >= top[2] - DEPTH_TOL_MM:
                        continue
                    other = _placed_footprint(top, angle, pallet.box)
                    if _area(_clip(_ccw(foot), other)) > AREA_TOL * pallet.box[0] * pallet.box[1]:
                        return (
                            f"{move.name}: on the move from {before.name} the carried {held}'s bottom passes "
                            f"{top[2] - bottom:.1f} mm below the top of {_name(placed[i])}"
                        )
    return None


def _name(p) -> str:
    return f"layer {p.layer} box {p.number}"


def _placed_footprint(top: np.ndarray, angle_deg: float, size) -> np.ndarray:
    a = np.radians(angle_deg)
    c, s = np.cos(a), np.sin(a)
    half = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]]) * np.asarray(size[:2]) / 2
    return half @ np.array([[c, s], [-s, c]]) + top[:2]


def _ccw(polygon: np.ndarray) -> np.ndarray:
    """The polygon counterclockwise (a tool turned upside down mirrors the footprint's order)."""
    x, y = polygon[:, 0], polygon[:, 1]
    return polygon if float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))) >= 0 else polygon[::-1]
