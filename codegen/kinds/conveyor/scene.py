"""The belt in the cell's page (codegen/view/): the belt in its frame, the pick window, the camera's line, the place."""

from __future__ import annotations

import numpy as np

from codegen import protocol
from codegen.view.scene import SLAB_MM, box, frame, line, translated

MARGIN_MM = 150.0  # the belt drawn this far beyond its window and the camera's line
PLACE_TABLE_MM = (200.0, 200.0, 100.0)  # the place's table as drawn: its size, and how far under the place


def objects(cell, conveyor) -> list[dict]:
    """The belt (y the travel, z up; the origin the downstream touch), the window, the camera's line upstream and
    the place."""
    belt2base = conveyor.frame()
    if belt2base is None:
        return []
    pick = conveyor.pick
    across = pick.x_range_mm if pick is not None else (-100.0, 100.0)
    window = pick.window_mm if pick is not None else (0.0, 0.0)
    camera = -(conveyor.camera_offset_mm or 0.0)
    start, end = min(camera, window[0]) - MARGIN_MM, max(0.0, window[1]) + MARGIN_MM
    x0, x1 = across[0] - MARGIN_MM / 3, across[1] + MARGIN_MM / 3
    centre = translated(belt2base, ((x0 + x1) / 2, (start + end) / 2, -SLAB_MM / 2))
    out = [box(centre, (x1 - x0, end - start, SLAB_MM), "belt", "belt"), frame(belt2base, "belt frame", "belt", 100.0)]
    if conveyor.camera_offset_mm is not None:
        out.append(line([belt2base @ np.array([x, camera, 1.0, 1.0]) for x in (x0, x1)], "camera", "camera line"))
    if pick is not None:
        corners = [(across[0], window[0]), (across[1], window[0]), (across[1], window[1]), (across[0], window[1])]
        ring = [belt2base @ np.array([x, y, 1.0, 1.0]) for x, y in [*corners, corners[0]]]
        out.append(line(ring, "window", "pick window"))
        place = pick.place.matrix()
        out.append(frame(place, "place", "place"))
        table = np.eye(4)
        table[:3, 3] = place[:3, 3] - (0.0, 0.0, PLACE_TABLE_MM[2])
        out.append(box(table, (*PLACE_TABLE_MM[:2], SLAB_MM), "place", "place table"))
    return out


class ScenePart(protocol.Scene):
    def objects(self, cell) -> list[dict]:
        section = self.kind.section.of(cell)
        return [] if section is None else objects(cell, section)
