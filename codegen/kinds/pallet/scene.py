"""The pallets in the cell: as the page draws them (each pallet, its boxes layer by layer, slip sheets, pick place)
and as solids (the pallet, the pick place and the stack as built)."""

from __future__ import annotations

import numpy as np

from codegen import protocol
from codegen.kinds.pallet.analysis import frame_matrix
from codegen.kinds.pallet.patterns import label_normal
from codegen.kinds.pallet.stack import layer_top, placements
from codegen.poses import matrix_from_rotation_translation, rotmat_from_zyx_deg
from codegen.view.scene import SLAB_MM, box, frame, translated
from codegen.world.solids import Box

PALLET_HEIGHT_MM = 144.0  # a EUR pallet's height (EN 13698-1): the pallet's solid under its top
PICK_PLACE_SCALE = 1.5  # the pick place's top reaches this many box sizes around Q (as the page draws it)
PICK_PLACE_DEPTH_MM = 100.0  # the pick place's solid under its top: the top plate of what holds the box at Q

LABEL_MM = 1.0  # a box's label, drawn as a sheet this thick on its label side
GAP_MM = 2.0  # boxes drawn this much narrower than they are, so that neighbours show apart


def objects(cell, pallets) -> list[dict]:
    out = []
    for pallet in pallets:
        out += _pallet(pallet)
    return out


def _pallet(pallet) -> list[dict]:
    """The pallet (its top at the frame's z = 0), every box of the full stack with its label right after it (the
    page's box events rely on that order), the slip sheets and the pick place Q."""
    pallet2base = frame_matrix(pallet)
    length, width = pallet.size
    out = [
        box(translated(pallet2base, (length / 2, width / 2, -SLAB_MM / 2)), (length, width, SLAB_MM), "wood"),
        frame(pallet2base, f"pallet {pallet.name}", "wood", 120.0),
    ]
    bx, by, bz = pallet.box
    face = by / 2 - GAP_MM / 2 + LABEL_MM / 2
    for p in placements(pallet):
        top = layer_top(pallet, p.layer)
        turn = rotmat_from_zyx_deg(p.box.ccw_deg, 0.0, 0.0)
        centre = pallet2base @ matrix_from_rotation_translation(turn, (p.box.x, p.box.y, top - bz / 2))
        size = (bx - GAP_MM, by - GAP_MM, bz)
        out.append(box(centre, size, "box", f"{pallet.name}: layer {p.layer} box {p.number}"))
        nx, ny = label_normal(p.box)  # the label on the long side at -y at angle 0
        label = pallet2base @ matrix_from_rotation_translation(
            turn, (p.box.x + nx * face, p.box.y + ny * face, top - bz / 2)
        )
        out.append(box(label, (bx * 0.5, LABEL_MM, bz * 0.5), "label"))
    if pallet.slip_every:
        for layer in range(pallet.slip_every, pallet.layers, pallet.slip_every):
            z = layer_top(pallet, layer) + pallet.slip_thickness / 2
            sheet = translated(pallet2base, (length / 2, width / 2, z))
            out.append(box(sheet, (length, width, max(pallet.slip_thickness, 1.0)), "sheet", f"slip sheet {layer}"))
    if pallet.pick is not None:
        pick = pallet.pick.matrix()
        out.append(frame(pick, f"pallet {pallet.name}: pick Q", "pick"))
        table = np.eye(4)
        table[:3, 3] = pick[:3, 3] - (0.0, 0.0, bz + SLAB_MM / 2)
        out.append(box(table, (bx * 1.5, by * 1.5, SLAB_MM), "pick", "pick place"))
    return out


def solids(pallets) -> dict[str, Box]:
    """Each pallet (its top at the frame's z = 0, PALLET_HEIGHT_MM deep) and its pick place (a plate whose top is a
    box's height under Q, where the box Q holds stands). The stack is not among them: it grows while the program
    runs (stack_solids)."""
    out = {}
    for pallet in pallets:
        length, width = pallet.size
        centre = translated(frame_matrix(pallet), (length / 2, width / 2, -PALLET_HEIGHT_MM / 2))
        out[f"pallet {pallet.name}"] = Box((length, width, PALLET_HEIGHT_MM), centre)
        if pallet.pick is not None:
            bx, by, bz = pallet.box
            plate = np.eye(4)
            plate[:3, 3] = pallet.pick.matrix()[:3, 3] - (0.0, 0.0, bz + PICK_PLACE_DEPTH_MM / 2)
            size = (bx * PICK_PLACE_SCALE, by * PICK_PLACE_SCALE, PICK_PLACE_DEPTH_MM)
            out[f"pallet {pallet.name}: pick place"] = Box(size, plate)
    return out


def stack_solids(pallet, boxes: int) -> dict[str, Box]:
    """The stack with its first `boxes` boxes on the pallet (in placing order; unstacking takes the last first):
    every full layer below the top one as one box over the pallet's area and the layer's height (a bound of its
    boxes, the overhang added), the top layer's boxes each as placed."""
    placed = placements(pallet)[:boxes]
    if not placed:
        return {}
    pallet2base = frame_matrix(pallet)
    length, width = pallet.size
    bx, by, bz = pallet.box
    top_layer = placed[-1].layer
    out = {}
    if top_layer > 1:
        below = layer_top(pallet, top_layer - 1)
        grow = 2 * pallet.overhang_mm
        centre = translated(pallet2base, (length / 2, width / 2, below / 2))
        out[f"pallet {pallet.name}: stack below layer {top_layer}"] = Box((length + grow, width + grow, below), centre)
    top = layer_top(pallet, top_layer)
    for p in placed:
        if p.layer != top_layer:
            continue
        turn = rotmat_from_zyx_deg(p.box.ccw_deg, 0.0, 0.0)
        centre = pallet2base @ matrix_from_rotation_translation(turn, (p.box.x, p.box.y, top - bz / 2))
        out[f"pallet {pallet.name}: layer {p.layer} box {p.number}"] = Box((bx, by, bz), centre)
    return out


class ScenePart(protocol.Scene):
    def objects(self, cell) -> list[dict]:
        return objects(cell, self.kind.section.of(cell) or ())

    def solids(self, cell) -> dict[str, Box]:
        return solids(self.kind.section.of(cell) or ())
