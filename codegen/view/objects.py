"""The cell's objects in the page: each kind's (its scene part), in the order of the kinds the cell was loaded with."""

from __future__ import annotations


def cell_objects(cell) -> list[dict]:
    return [o for kind in cell.kinds.values() for o in kind.scene.objects(cell)]
