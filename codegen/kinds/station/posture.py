"""The posture each station is worked in where the cell names none: the arm configuration whose moves clear the cell."""

# Where the cell gives no configuration for a station on a target ([station.config.<target>]), the controller leaves the
# choice to the program: the joints a program steers its inverse kinematics to, or the configuration fields a Cartesian
# target carries (codegen/robot/config.py). The candidates, their order and ranking are codegen/world/posture.py's;
# the linear moves continue in each. Each must pass the reach proof over the correction region (joint limits and the
# cell's joint margin, the wrist margin, no change of configuration) and the clearance proof (codegen/world/proof.py) of
# the station's moves at the nominal reading, which ranks them; one that would replace the nearest-home posture must
# clear at every other proven reading too, and the one kept is proven at every proven reading (by its choice, or by
# generate where the choice proved only the nominal one). The choice is written as taught joints (PoseConfig "joints"):
# each target's program names them in its own form (codegen/robot/config.py FORMS), and verify expects them by the
# same rule.

from __future__ import annotations

from dataclasses import replace

import numpy as np

from codegen.kinds.station.envelope import station_margin
from codegen.kinds.station.mode import mode_of
from codegen.kinds.station.region import station_region
from codegen.kinds.station.scene import station_paths
from codegen.kinds.station.section import stations_of, with_section
from codegen.model.robot import PoseConfig
from codegen.robot import solve
from codegen.robot.taught import ReachError
from codegen.world.posture import TIE_MM, Posture, branch_joints, choose, set_by_the_tool, travel


def decide(cell, target: str, station) -> tuple[dict, str, tuple | None]:
    """The configuration per pose the station's program takes on the target, the posture note and the proofs the choice
    made of it. The configuration: the cell's own ([station.config]) where it gives one, else the chosen posture's ({}
    where none reaches and clears: the nearest-home solutions, which the proofs then refuse with their reasons). The
    note: '' where the station is worked in the posture the controller takes from the home by itself (or the cell names
    it); else what was chosen and why, in the target's own form (generate's report). The proofs: (the region, the
    envelope margins, the least clearances of the station's paths or None where only the nominal reading was proven)
    of the posture kept, where the choice proved it; None: not proven here."""
    given = station.config.get(target)
    if given:
        return given, "", None
    tried = candidates(cell, target, station)
    if not tried:
        return {}, "", None
    natural = evaluate(cell, target, station, tried[0])
    if not natural.reaches:
        return {}, "", None
    if natural.least_mm is not None and set_by_the_tool(cell.robot.arms[target], natural.nearest):
        return natural.config, "", natural.proven
    best = choose(natural, tried[1:], lambda posture, bar: evaluate(cell, target, station, posture, bar, every=True))
    if best is None:
        return {}, "", None
    if best is natural:
        return natural.config, "", natural.proven
    return best.config, _note(cell, target, natural, best), best.proven


def _note(cell, target: str, natural: Posture, best: Posture) -> str:
    from codegen.controllers import get_target
    from codegen.robot.taught import configuration

    arm = cell.robot.arms[target]
    form = get_target(target).configuration
    name, first = next(iter(best.config.items()))
    value = configuration(form, arm, np.asarray(first.value))
    shown = ", ".join(f"{v:.6g}" for v in value)
    why = "does not clear"
    if natural.least_mm is not None:
        why = f"keeps {natural.least_mm:.1f} mm (more than {TIE_MM:g} mm less)"
    return (
        f"posture chosen to clear the cell: pose {name!r} in configuration [{shown}] ({form}), least clearance "
        f"{best.least_mm:.1f} mm at the nominal reading; the configuration nearest the home {why}"
    )


def candidates(cell, target: str, station) -> list[Posture]:
    """The postures tried, the one the controller takes from the home by itself first (each joint pose's solution
    nearest the home), then each branch that takes every joint pose within the joint limits (each nearest the home
    within the branch), nearer the home first; [] where a joint pose has no solution within the limits (the reach
    proof names it)."""
    robot = cell.robot
    arm, home = robot.arms[target], np.asarray(robot.home[target], dtype=float)
    poses = mode_of(station).arm_poses(cell, station)
    joint = [(name, tcp) for name, tcp, motion in poses if motion == "joint"]
    if not joint:
        return []
    solutions = solve.branches(arm, solve.flange_poses(np.array([tcp for _, tcp in joint]), robot.tool.tcp2flange))
    natural, others = branch_joints(arm, solutions, home)
    if np.isnan(natural).any():
        return []
    return [_posture(joint, natural, -1, home), *(_posture(joint, q, b, home) for b, q in others)]


def _posture(joint: list, q: np.ndarray, branch: int, home: np.ndarray) -> Posture:
    """The posture taking joints q (one row per joint pose) as PoseConfig "joints"; travel: its first pose's."""
    config = {name: PoseConfig("joints", tuple(float(v) for v in row)) for (name, _), row in zip(joint, q, strict=True)}
    return Posture(config, branch, travel(q[0], home))


def evaluate(cell, target: str, station, posture: Posture, bar: float | None = None, every: bool = False) -> Posture:
    """The posture with its least clearance along the station's moves at the nominal reading, or its refusal (reach
    over the correction region, or clearance: within the cell's clearance, or within bar mm where that is more). The
    nominal reading ranks the postures; every: one that passes its bar there is proven at every other proven reading
    too (before it replaces the nearest-home one). A posture that passes carries its proofs (Posture.proven): its
    region, its envelope margins and, where every reading was proven, each path's least clearance (the kind's plan,
    codegen/kinds/station/plan.py, hands them on)."""
    from codegen.world.proof import ClearanceError, prove  # coal: loaded only when proving

    tried = with_posture(cell, target, station, posture.config)
    moved = next(s for s in stations_of(tried) if s.id == station.id)
    try:
        region = station_region(tried, target, moved)
        margin = station_margin(tried, target, moved, region)
    except ReachError as exc:
        return replace(posture, refusal=str(exc), reaches=False)
    try:
        paths = station_paths(tried, target, moved, region)
        least = prove(tried, paths[:1], bar)
        rest = prove(tried, paths[1:]) if every else None
    except (ClearanceError, ValueError) as exc:
        return replace(posture, refusal=str(exc))
    nearest = min(least, key=lambda x: x.found.distance)
    # the bar only refuses: a path that passes it has the least clearance generate's proof finds
    proven = None if rest is None else (*least, *rest)
    return replace(posture, least_mm=nearest.found.distance, nearest=nearest, proven=(region, margin, proven))


def with_posture(cell, target: str, station, config: dict):
    """The cell with the station's configuration on the target given as config (the other stations as they are)."""
    changed = tuple(
        replace(s, config={**s.config, target: config}) if s.id == station.id else s for s in stations_of(cell)
    )
    return with_section(cell, stations=changed)
