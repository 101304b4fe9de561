"""The cell's objects in the page: the solids the cell declares, then each kind's (its scene part), in the order of
the kinds the cell was loaded with."""

from __future__ import annotations

from codegen.view.scene import box, cylinder
from codegen.world.cell import declared
from codegen.world.solids import Box, Cylinder

SOLID_OPACITY = 0.45  # a keep-out solid drawn see-through: the arm is seen inside a machine it reaches into


def cell_objects(cell) -> list[dict]:
    return [*solid_objects(cell), *(o for kind in cell.kinds.values() for o in kind.scene.objects(cell))]


def solid_objects(cell) -> list[dict]:
    """The keep-out solids [cell.world] declares (the floor is the page's grid; each kind draws its own)."""
    out = []
    for name, solid in declared(cell).items():
        if isinstance(solid, Box):
            out.append(box(solid.pose, solid.size, "solid", name, SOLID_OPACITY))
        elif isinstance(solid, Cylinder):
            out.append(cylinder(solid.pose, solid.radius, solid.length, "solid", name, SOLID_OPACITY))
    return out
