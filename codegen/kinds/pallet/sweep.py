"""The gripper's sweep: the carried box (sheet) or empty gripper never below the tops of the boxes under it."""

from __future__ import annotations

import itertools

import numpy as np

from codegen.kinds.pallet.checks import AREA_TOL, _area, _clip
from codegen.kinds.pallet.shape import PalletShape
from codegen.poses import rotmat_from_zyx_deg

SAMPLES = 64  # points along each segment (and its two ends)
DEPTH_TOL_MM = 1e-6  # a bottom resting on a top is not below it
PLACE_POSES = ("entry", "approach", "target", "retreat")  # a box's own last descent (first ascent)
# The empty gripper's face, where the cell gives no gripper's size: a square this wide (mm) about the TCP, in the
# plane of the TCP (a stated clearance: 50 mm on every side of the TCP point, in the tool's x and y)
EMPTY_GRIPPER_MM = 100.0


def _own(name: str) -> tuple[str, str]:
    """("layer L box N", pose) of a move's name ("layer L sheet", pose: the slip sheet below layer L; "", name: a move
    of no box, as off the pallet at the end or home)."""
    words = name.split()
    if words[:1] != ["layer"] or len(words) < 3:
        return "", name
    if words[2] == "sheet":
        return " ".join(words[:3]), " ".join(words[3:])
    return " ".join(words[:4]), " ".join(words[4:])


def _positions(before, move, fk) -> np.ndarray:
    """The tcp2base poses along a move: a joint move with joints (fk given: (n, 6) -> (n, 4, 4)) a straight line in
    joint space, as the controller moves; else the straight segment of the TCP, once with each end's orientation."""
    ts = np.linspace(0.0, 1.0, SAMPLES + 1)
    qa, qb = getattr(before, "joints", None), getattr(move, "joints", None)
    if move.kind == "joint" and fk is not None and qa is not None and qb is not None:
        qa, qb = np.asarray(qa, dtype=float), np.asarray(qb, dtype=float)
        return fk(qa[None] + ts[:, None] * (qb - qa)[None])
    a, b = before.tcp2base, move.tcp2base
    out = np.zeros((2, len(ts), 4, 4))
    out[:, :, 3, 3] = 1.0
    out[0, :, :3, :3], out[1, :, :3, :3] = a[:3, :3], b[:3, :3]
    out[:, :, :3, 3] = a[:3, 3] + ts[:, None] * (b[:3, 3] - a[:3, 3])
    return out.reshape(-1, 4, 4)


def _on_pallet(pallet, moves, order) -> list[set[int] | None]:
    """Per move, the boxes (indices into placements) on the pallet while it is made: stacking those placed before
    the first box the moves name and each box once the gripper let it go; unstacking those up to the first box the
    moves name, each gone once gripped. None before the first move that names a box."""
    stack = pallet.mode == "stack"
    on: set[int] | None = None
    out = []
    for before, move in itertools.pairwise([None, *moves]):
        own = order.get(_own(move.name)[0]) if _own(move.name)[0].split()[2:3] == ["box"] else None
        if on is None:
            first = next((order[o] for m in moves if (o := _own(m.name)[0]) in order), None)
            if first is not None:
                on = set(range(first if stack else first + 1))
        fresh = before is None or _own(before.name)[0] != _own(move.name)[0]  # the first move of its item
        if on is not None and own is not None and fresh and (own in on) == stack:  # the pallet was swapped
            on = set(range(own if stack else own + 1))  # the new one as it was made (taken) up to this box
        if on is not None and before is not None and own is not None and _own(before.name)[0] == _own(move.name)[0]:
            if stack and before.carrying and not move.carrying:
                on.add(own)  # let go on its place
            if not stack and move.carrying and not before.carrying:
                on.discard(own)  # off the pallet
        out.append(None if on is None else set(on))
    return out


def sweeps(shape: PalletShape, moves, fk=None, gripper_mm: float = 0.0) -> str | None:
    """The first move (ExpectedMove: kind, tcp2base, name, carrying or sheet; joints where fk is given) whose path
    from the move before it takes the carried box's (the sheet's) bottom, or the empty gripper's face, below the top
    of a box on the pallet under its footprint; None: none. A carried box is checked against the boxes placed before
    it, on every move but its own last descent (first ascent); the empty gripper (a square gripper_mm wide about the
    TCP: the cell gives no gripper's size) against the boxes on the pallet then, on every move but those at its own
    box's place. A joint move with joints is followed through joint space (fk: joints -> tcp2base); another move as
    the TCP's straight segment. A slip sheet is taken as the pallet's size (the cell gives its thickness alone) and
    lies below its layer's first box."""
    pallet, placed = shape.pallet, shape.placements
    tool = rotmat_from_zyx_deg(*pallet.tool_orientation)
    base2pallet = np.linalg.inv(shape.pallet2base)
    order = {f"layer {p.layer} box {p.number}": i for i, p in enumerate(placed)}
    order |= {f"layer {p.layer} sheet": i for i, p in enumerate(placed) if p.number == 1}
    sheet = (pallet.size[0], pallet.size[1], pallet.slip_thickness)
    shapes = [(p.target[:3, 3], p.box.ccw_deg) for p in placed]
    empty = (gripper_mm, gripper_mm, 0.0)
    present = _on_pallet(pallet, moves, order)
    for k, (before, move) in enumerate(itertools.pairwise(moves), start=1):
        held = "sheet" if getattr(move, "sheet", False) else "box" if move.carrying else None
        (own_a, pose_a), (own_b, pose_b) = _own(before.name), _own(move.name)
        at_place = own_a == own_b and pose_a in PLACE_POSES and pose_b in PLACE_POSES
        if held is None:
            if present[k] is None:
                continue
            others = present[k] - ({order[own_b]} if at_place and own_b in order else set())
            size, what = empty, "empty gripper's face"
        else:
            mine = order.get(own_b)
            if at_place or mine is None:
                continue
            others = set(range(mine))  # the boxes placed before it (unstacking: still on the pallet under it)
            size, what = (sheet if held == "sheet" else pallet.box), f"carried {held}'s bottom"
        found = _first_crossing(base2pallet, _positions(before, move, fk), tool, size, others, shapes, pallet.box)
        if found is not None:
            i, depth = found
            return (
                f"{move.name}: on the move from {before.name} the {what} passes {depth:.1f} mm below the top of "
                f"{_name(placed[i])}"
            )
    return None


def _first_crossing(base2pallet, poses, tool, size, others, shapes, box) -> tuple[int, float] | None:
    """The first box (index, depth mm) under the footprint at one of the poses with its top above the footprint's
    bottom; None: none. Poses above every top, or boxes far off in x-y, are passed over before the exact test."""
    if not others:
        return None
    ids = sorted(others)
    tops = np.array([shapes[i][0] for i in ids])
    local = base2pallet @ np.asarray(poses)
    axes = local[:, :3, :3] @ tool.T  # the footprint's axes: the tool's at box angle 0
    half = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]]) * np.asarray(size[:2]) / 2
    corners = local[:, None, :3, 3] + half @ axes[:, :, :2].transpose(0, 2, 1) - size[2] * axes[:, None, :, 2]
    bottoms = corners[:, :, 2].min(axis=1)
    centres = corners[:, :, :2].mean(axis=1)
    reach = np.hypot(*size[:2]) / 2 + np.hypot(*box[:2]) / 2 + 1.0  # centres farther apart: no overlap
    low = tops[None, :, 2] - DEPTH_TOL_MM > bottoms[:, None]
    near = np.hypot(tops[None, :, 0] - centres[:, None, 0], tops[None, :, 1] - centres[:, None, 1]) <= reach
    for n, k in zip(*np.nonzero(low & near), strict=True):
        top, angle = shapes[ids[k]]
        if _overlap(corners[n, :, :2], _placed_footprint(top, angle, box), size, box):
            return ids[k], float(top[2] - bottoms[n])
    return None


def _overlap(foot: np.ndarray, other: np.ndarray, size, box) -> bool:
    """Two footprints share more than touching (a point gripper: lies inside)."""
    if size[0] * size[1] == 0:
        return bool(_inside(foot[0], other))
    limit = AREA_TOL * min(size[0] * size[1], box[0] * box[1])
    return _area(_clip(_ccw(foot), other)) > limit


def _inside(point: np.ndarray, polygon: np.ndarray) -> bool:
    """A point strictly inside a counterclockwise convex polygon."""
    edges = np.roll(polygon, -1, axis=0) - polygon
    rel = point[None, :2] - polygon
    return bool(np.all(edges[:, 0] * rel[:, 1] - edges[:, 1] * rel[:, 0] > DEPTH_TOL_MM))


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
