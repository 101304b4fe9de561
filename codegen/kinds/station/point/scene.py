"""A point-mode station in the cell's page (codegen/view/): its mark at calibration and its taught poses."""

from __future__ import annotations

from codegen.poses import matrix_from_rotation_translation, rotmat_from_zyx_deg
from codegen.view.scene import frame, line


def objects(cell, station) -> list[dict]:
    """The mark at calibration (x, y, theta in the base frame: drawn at the work pose's height, the cell gives no
    height) and the taught poses in the order the arm visits them."""
    x, y, theta = station.spec.mark
    work = station.poses[-1].matrix()
    mark = matrix_from_rotation_translation(rotmat_from_zyx_deg(theta, 0.0, 0.0), (x, y, work[2, 3]))
    out = [frame(mark, f"{station.name}: mark", "mark", 40.0)]
    out += [frame(p.matrix(), f"{station.name}: {p.name}", "taught") for p in station.path]
    out.append(line([p.matrix()[:3, 3] for p in station.path], "taught", dashed=True))
    return out
