"""The pallets in the cell's page (codegen/view/): each pallet, its boxes layer by layer, slip sheets, pick place."""

from __future__ import annotations

import numpy as np

from codegen import protocol
from codegen.kinds.pallet.analysis import frame_matrix
from codegen.kinds.pallet.patterns import label_normal
from codegen.kinds.pallet.stack import layer_top, placements
from codegen.poses import matrix_from_rotation_translation, rotmat_from_zyx_deg
from codegen.view.scene import SLAB_MM, box, frame, translated

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


class ScenePart(protocol.Scene):
    def objects(self, cell) -> list[dict]:
        return objects(cell, self.kind.section.of(cell) or ())
