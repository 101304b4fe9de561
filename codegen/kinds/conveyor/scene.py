"""The belt in the cell: as the page draws it (the belt in its frame, the pick window, the camera's line, the place)
and as solids (the belt, the place's table)."""

from __future__ import annotations

import numpy as np

from codegen import protocol
from codegen.view.scene import SLAB_MM, box, frame, line, translated
from codegen.world.solids import Box

MARGIN_MM = 150.0  # the belt drawn this far beyond its window and the camera's line
PLACE_TABLE_MM = (200.0, 200.0, 100.0)  # the place's table as drawn: its size, and how far under the place
BELT_DEPTH_MM = 150.0  # the belt's solid under its surface: the belt, its rollers and frame (an estimate)


def _extent(conveyor) -> tuple[tuple[float, float], tuple[float, float]]:
    """The belt's drawn extent in its frame, across (x) and along (y): the window and the camera's line, a margin
    around."""
    pick = conveyor.pick
    across = pick.x_range_mm if pick is not None else (-100.0, 100.0)
    window = pick.window_mm if pick is not None else (0.0, 0.0)
    camera = -(conveyor.camera_offset_mm or 0.0)
    start, end = min(camera, window[0]) - MARGIN_MM, max(0.0, window[1]) + MARGIN_MM
    return (across[0] - MARGIN_MM / 3, across[1] + MARGIN_MM / 3), (start, end)


def solids(conveyor) -> dict[str, Box]:
    """The belt (its surface the frame's z = 0, BELT_DEPTH_MM deep, as far as the page draws it) and, where the part's
    size is given, the place's table: its top under the placed part's bottom (the part as the tool holds it)."""
    belt2base = conveyor.frame()
    if belt2base is None:
        return {}
    (x0, x1), (start, end) = _extent(conveyor)
    centre = translated(belt2base, ((x0 + x1) / 2, (start + end) / 2, -BELT_DEPTH_MM / 2))
    out = {"belt": Box((x1 - x0, end - start, BELT_DEPTH_MM), centre)}
    pick = conveyor.pick
    if pick is not None and pick.part_size_mm is not None:
        cog, size = pick.part_cog_mm, pick.part_size_mm
        bottom = pick.place.matrix() @ np.array([cog[0], cog[1], cog[2] + size[2] / 2, 1.0])
        table = np.eye(4)
        table[:3, 3] = bottom[:3] - (0.0, 0.0, PLACE_TABLE_MM[2] / 2)
        out["belt: place table"] = Box(PLACE_TABLE_MM, table)
    return out


def objects(cell, conveyor) -> list[dict]:
    """The belt (y the travel, z up; the origin the downstream touch), the window, the camera's line upstream and
    the place."""
    belt2base = conveyor.frame()
    if belt2base is None:
        return []
    pick = conveyor.pick
    camera = -(conveyor.camera_offset_mm or 0.0)
    across = pick.x_range_mm if pick is not None else (-100.0, 100.0)
    window = pick.window_mm if pick is not None else (0.0, 0.0)
    (x0, x1), (start, end) = _extent(conveyor)
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

    def solids(self, cell) -> dict[str, Box]:
        section = self.kind.section.of(cell)
        return {} if section is None else solids(section)
