"""The part a station's gripper carries: [station.part] read, its load with the tool's, and the part followed through
a run (where the gripper closed and opened, with or without a part, judged against the grip and release poses)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from codegen.kinds.station.keys import GRIP, PART, RELEASE
from codegen.model.loader import Loader
from codegen.model.world import PartShape
from codegen.world import loads
from codegen.world.solids import translation


@dataclass(frozen=True)
class Part(PartShape):
    """[station.part]: the box hanging from the TCP (PartShape), its mass (kg; 0: the load stays the tool's) and its
    centre of gravity in the TCP frame (mm; None: the box's centre)."""

    mass_kg: float = 0.0
    cog_mm: tuple[float, float, float] | None = None


def read_part(ctx, raw, path: str) -> Part | None:
    """[station.part] read by its declaration (keys.PART); None where not given."""
    if raw is None:
        return None
    values = Loader(ctx).table(PART, raw, path)
    cog = values["cog_mm"]
    return Part(tuple(values["size_mm"]), values["mass_kg"], None if cog is None else tuple(cog))


def part_alone(part: Part | None) -> loads.Load | None:
    """The part in the TCP frame (a payload's frame): a solid box of its size hanging from the TCP along the tool's z,
    its inertia about its centre; at a declared centre of gravity, that inertia about it (as a tool's, loads.of_tool);
    None: no mass given."""
    if part is None or not part.mass_kg > 0:
        return None
    size = tuple(float(v) for v in part.size_mm)
    centre2tcp = translation(0.0, 0.0, 0.5 * size[2])
    shape = loads.held_box(part.mass_kg, size, centre2tcp, np.eye(4))
    if part.cog_mm is None:
        return shape
    return loads.Load(shape.mass, np.asarray(part.cog_mm, dtype=float), shape.inertia_cog)


def part_load(cell, station) -> loads.Load | None:  # station: a section.Station (which reads Part from here)
    """The load while the station's part is in the gripper: the tool's and the part's as one, in the flange frame
    (mass, common centre of gravity, the tensor about it with the parallel-axis terms); None: the part has no mass,
    or the cell gives no tool (the programs then set no load)."""
    robot, given = cell.robot, None if station is None else station.part
    key = (id(robot), id(given))
    hit = _LOADS.get(key)
    if hit is not None and hit[0] is robot and hit[1] is given:  # a case's judgement asks again for each case
        return hit[2]
    part = part_alone(given)
    load = None
    if robot is not None and robot.tool_given and part is not None:
        load = loads.with_tool(robot.tool, robot.tool_shaped, part)
    if load is not None:
        load.cog_mm.flags.writeable = load.inertia_cog.flags.writeable = False  # shared by every caller
    if len(_LOADS) >= 256:
        _LOADS.clear()
    _LOADS[key] = (robot, given, load)  # both held, so that their ids stay theirs while remembered
    return load


_LOADS: dict[tuple[int, int], tuple] = {}  # part_load by the robot's and the part's identity (frozen: never changed)


def held_part(cell, stations):  # -> a section.Station or None
    """The first station whose part a gripper holding one at the start carries, where that load is known before the
    station is (every station that grips carries a part of the same load): its load is set before the move home;
    None: a station grips a part without mass, or two parts differ (the load is set once the station is known)."""
    gripping = [s for s in stations if s.gripper]
    found = [part_load(cell, s) for s in gripping]
    if not found or any(load is None for load in found):
        return None
    first = found[0].flat()
    return gripping[0] if all(load.flat() == first for load in found) else None


def part_problem(cell, output: str, station, moves, held: bool, trace, tolerance_mm: float) -> str | None:
    """The first place where the run mishandles the part, None: none. `output` is the gripper's output as the
    program names it, `moves` the reference's moves through the station (their poses where the gripper may act),
    `held` whether a part is in the gripper at the start. A part may be taken only at rest at a grip pose, put
    down only at rest at a release pose; the gripper closed elsewhere holds nothing (it finds no part there)."""
    poses = {GRIP: [], RELEASE: []}
    if station is not None:
        for move in moves:
            action = station.action(move.pose_name)
            if action is not None:
                poses[action].append((move.pose_name, move.tcp2base[:3, 3]))
    for event in trace.outputs:
        if event.name != output:
            continue
        closes = event.value == cell.io.value
        where = _where(event)
        if closes and held:
            continue  # gripped again on the part it holds (the start after a stop)
        if closes:
            name = _at(poses[GRIP], event, tolerance_mm)
            if event.moving or name is None:
                grips = _names(poses[GRIP])
                return f"the gripper closed {where}: no part is taken there (the grip poses on its path: {grips})"
            held = True
        elif held:
            name = _at(poses[RELEASE], event, tolerance_mm)
            if event.moving or name is None:
                return (
                    f"the gripper opened with a part {where}: the part is dropped there, not put down at a release "
                    f"pose ({_names(poses[RELEASE])})"
                )
            held = False
    return None


def _at(candidates: list, event, tolerance_mm: float) -> str | None:
    if event.tcp2base is None:
        return None
    return next(
        (name for name, point in candidates if float(np.linalg.norm(event.tcp2base[:3, 3] - point)) <= tolerance_mm),
        None,
    )


def _where(event) -> str:
    state = "while the arm moves" if event.moving else "at rest"
    if event.tcp2base is None:
        return f"(line {event.line}, {state}, the tool's pose unknown)"
    x, y, z = (float(v) for v in event.tcp2base[:3, 3])
    return f"at ({x:.3f}, {y:.3f}, {z:.3f}) mm (line {event.line}, {state}, after move {event.after_moves})"


def _names(candidates: list) -> str:
    return ", ".join(name for name, _ in candidates) or "none"
