"""The part followed through a station program's run: where the gripper closed and opened, with or without a part,
judged against the station's grip and release poses from the tool's pose at each of those moments."""

from __future__ import annotations

import numpy as np

from codegen.kinds.station.keys import GRIP, RELEASE


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
