"""A cell's solid objects for one target's arm: the floor, the declared solids, every kind's own, the tool and part."""

from __future__ import annotations

import numpy as np

from codegen.model.world import PartShape
from codegen.world.engine import Scene
from codegen.world.solids import Box, Cylinder, Floor, Solid, World, part_box, shape_of, tool_box, tool_cylinder

FLOOR = "floor"  # the floor's (or mounting plane's) name among the solids
# the link frames only axis 1 moves (the base, and the column turning about axis 1, which stands perpendicular to the
# mounting plane): their height above the floor never changes, so they are not measured against it (a column that
# reaches into its mounting plate would otherwise refuse every move)
FLOOR_EXEMPT_FRAMES = 1


def clearance_mm(cell) -> float:
    """The least distance every planned move keeps from the solids ([cell.world] clearance_mm)."""
    return float(cell.world.clearance_mm)


def declared(cell) -> dict[str, Solid]:
    """The floor and the solids [cell.world] declares, in the robot's base frame (mm)."""
    out: dict[str, Solid] = {FLOOR: Floor(cell.world.floor_z_mm)}
    out.update({name: shape_of(spec) for name, spec in cell.world.solids.items()})
    return out


def solids(cell) -> dict[str, Solid]:
    """Every solid of the cell: the floor, the declared ones, then each kind's (Scene.solids); a name given twice is
    a ValueError naming it (a declared solid may not take a kind's name)."""
    out = declared(cell)
    for kind in cell.kinds.values():
        for name, solid in kind.scene.solids(cell).items():
            if name in out:
                raise ValueError(f"cell.world.solids.{name}: a solid of the {kind.name} kind has this name; rename it")
            out[name] = solid
    return out


def tool_shape(cell) -> Box | Cylinder | None:
    """The tool as a solid in the flange frame ([cell.tool]: a box of box_mm or a cylinder of radius_mm from the
    flange to the TCP); None: no tool, or its TCP at the flange."""
    robot = cell.robot
    if robot is None or not robot.tool_given or not np.any(robot.tool.tcp2flange[:3, 3]):
        return None
    if robot.tool.box_mm is not None:
        return tool_box(robot.tool.box_mm, robot.tool.tcp2flange)
    return tool_cylinder(robot.tool.tcp2flange, robot.tool.radius_mm)


def part_shape(cell, part: PartShape | Box) -> Box:
    """A carried part in the flange frame: a PartShape hangs from the TCP (gripped at the middle of its top face);
    a Box is taken as given (already in the flange frame)."""
    if isinstance(part, Box):
        return part
    return part_box(tuple(part.size_mm), cell.robot.tool.tcp2flange)


def scene_of(
    cell,
    target: str,
    part: PartShape | Box | None = None,
    extra: dict[str, Solid] | None = None,
    exempt: frozenset[tuple[str, str]] = frozenset(),
) -> Scene:
    """The target's arm ([cell.robot]) with the cell's tool and the carried part (if given) among the cell's solids
    (solids(cell)) and `extra` ones (what stands only for a while: the stack as built so far); exempt: (body, solid)
    name pairs not measured (the part and the place it is put down on)."""
    if cell.robot is None or target not in cell.robot.arms:
        raise ValueError(f"the cell gives no arm for the {target} target ([cell.robot])")
    world = solids(cell)
    for name, solid in (extra or {}).items():
        if name in world:
            raise ValueError(f"two solids named {name!r}")
        world[name] = solid
    carried = None if part is None else part_shape(cell, part)
    arm = cell.robot.arms[target]
    standing = {(link.name, FLOOR) for link in arm.links if link.frame <= FLOOR_EXEMPT_FRAMES}
    return Scene(arm, World(world), tool_shape(cell), carried, frozenset(exempt) | standing)
