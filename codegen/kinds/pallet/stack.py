"""The pallet frame from three taught points, the layers, and every box's target, entry, approach and retreat."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from codegen.kinds.pallet.patterns import Box, layout
from codegen.kinds.pallet.section import Pallet
from codegen.poses import matrix_from_rotation_translation, rotmat_from_zyx_deg

MIN_POINT_MM = 10.0  # taught points closer than this give the axes too coarsely
MIN_ANGLE_DEG = 10.0  # O->PX and O->PY closer than this to one line: no plane


class FrameError(ValueError):
    pass


def pallet2base(origin, x_point, xy_point) -> np.ndarray:
    """Orthonormal: x along O->PX, z = x cross (PY - O) normalised, y = z cross x (docs/kinds/pallet.md; source
    004's eq. 1 takes (PY - O) itself as y, not orthogonal unless PY was taught square)."""
    o, px, py = (np.asarray(p, dtype=float) for p in (origin, x_point, xy_point))
    u, v = px - o, py - o
    for name, d in (("x_point", u), ("xy_point", v)):
        if np.linalg.norm(d) < MIN_POINT_MM:
            raise FrameError(f"frame.{name} is {np.linalg.norm(d):.3g} mm from the origin (at least {MIN_POINT_MM:g})")
    sine = np.linalg.norm(np.cross(u, v)) / (np.linalg.norm(u) * np.linalg.norm(v))
    if sine < math.sin(math.radians(MIN_ANGLE_DEG)):
        raise FrameError(
            f"frame: origin, x_point and xy_point are within {MIN_ANGLE_DEG:g} deg of one line: they span no plane"
        )
    x = u / np.linalg.norm(u)
    z = np.cross(x, v)
    z /= np.linalg.norm(z)
    return matrix_from_rotation_translation(np.column_stack([x, np.cross(z, x), z]), o)


@dataclass(frozen=True)
class Placement:
    layer: int  # 1 = bottom
    number: int  # the box's 1-based number in its layer's pattern
    pattern: str
    box: Box
    target: np.ndarray  # 4x4, pallet frame
    entry: np.ndarray
    approach: np.ndarray
    retreat: np.ndarray


def layer_top(pallet: Pallet, layer: int) -> float:
    """z of the top of layer n (1 = bottom) in the pallet frame: n box heights and the slip sheets below it."""
    sheets = (layer - 1) // pallet.slip_every if pallet.slip_every else 0
    return layer * pallet.box[2] + sheets * pallet.slip_thickness


def pattern_of(pallet: Pallet, layer: int) -> str:
    return pallet.cycle[(layer - 1) % len(pallet.cycle)]


def side_offsets(pallet: Pallet, boxes: tuple[Box, ...], offset) -> list[tuple[float, float]]:
    """The x-y part of an approach (or retreat) offset for each box of a layer. Fixed: the cell's. With
    approach_auto: the same length, pointing from the centroid of the layer's earlier boxes (those placed
    before it; when unstacking, those still on the pallet) to the box, so the arm comes in from the open
    side and never over a box it could hit; the layer's first box: away from the pallet's centre."""
    if not pallet.approach_auto:
        return [(offset[0], offset[1])] * len(boxes)
    length = math.hypot(offset[0], offset[1])
    out = []
    for i, box in enumerate(boxes):
        if i:
            cx = sum(b.x for b in boxes[:i]) / i
            cy = sum(b.y for b in boxes[:i]) / i
        else:
            cx, cy = pallet.size[0] / 2, pallet.size[1] / 2
        dx, dy = box.x - cx, box.y - cy
        norm = math.hypot(dx, dy)
        out.append((offset[0], offset[1]) if norm < 1e-6 else (length * dx / norm, length * dy / norm))
    return out


def sides(pallet: Pallet, boxes: tuple[Box, ...]) -> list[tuple[tuple[float, float], tuple[float, float]]]:
    """Each box's x-y approach and retreat offsets."""
    approach, retreat = side_offsets(pallet, boxes, pallet.approach), side_offsets(pallet, boxes, pallet.retreat)
    return list(zip(approach, retreat, strict=True))


def placements(pallet: Pallet) -> list[Placement]:
    """Every box in placing order: layer by layer from the bottom, each in its pattern's order.
    Target = Trans(x, y, z_n) . Rz(ccw angle) . Rz(a0) Ry(b0) Rx(c0); entry, approach and retreat are
    the target moved by their offsets in the pallet frame."""
    tool = rotmat_from_zyx_deg(*pallet.tool_orientation)
    layouts = {name: layout(pallet, name) for name in set(pallet.cycle)}
    offsets_xy = {name: sides(pallet, boxes) for name, boxes in layouts.items()}
    out = []
    for layer in range(1, pallet.layers + 1):
        name, z = pattern_of(pallet, layer), layer_top(pallet, layer)
        for number, box in enumerate(layouts[name], start=1):
            (ax, ay), (rx, ry) = offsets_xy[name][number - 1]
            target = matrix_from_rotation_translation(
                rotmat_from_zyx_deg(box.ccw_deg, 0.0, 0.0) @ tool, (box.x, box.y, z)
            )
            offsets = ((0.0, 0.0, pallet.entry_dz), (ax, ay, pallet.approach[2]), (rx, ry, pallet.retreat[2]))
            moved = [_moved(target, offset) for offset in offsets]
            out.append(Placement(layer, number, name, box, target, *moved))
    return out


def _moved(pose: np.ndarray, offset) -> np.ndarray:
    out = pose.copy()
    out[:3, 3] += np.asarray(offset, dtype=float)
    return out
