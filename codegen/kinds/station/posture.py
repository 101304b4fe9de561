"""The posture each station is worked in where the cell names none: the arm configuration whose moves clear the cell."""

# Where the cell gives no configuration for a station on a target ([station.config.<target>]), the controller leaves the
# choice to the program: the joints a program steers its inverse kinematics to, or the configuration fields a Cartesian
# target carries (codegen/robot/config.py). The candidates, their order and ranking are codegen/world/posture.py's;
# the linear moves continue in each. Each must pass the reach proof over the correction region (joint limits and the
# cell's joint margin, the wrist margin, no change of configuration) and the clearance proof (codegen/world/proof.py) of
# the station's moves at the nominal reading, which ranks them; one that would replace the nearest-home posture must
# clear at every other proven reading too, and generate proves the one kept at every proven reading. The choice is
# written as taught joints (PoseConfig "joints"): each target's program names them in its own form
# (codegen/robot/config.py FORMS), and verify expects them by the same rule.

from __future__ import annotations

from dataclasses import replace

import numpy as np

from codegen.kinds.station.envelope import check as envelope_check
from codegen.kinds.station.envelope import station_margin
from codegen.kinds.station.mode import mode_of
from codegen.kinds.station.region import station_plan as region_plan
from codegen.kinds.station.scene import station_paths
from codegen.kinds.station.section import section_of, stations_of, with_section
from codegen.model.robot import PoseConfig
from codegen.robot import solve
from codegen.robot.cache import per_cell
from codegen.robot.taught import ReachError
from codegen.world.posture import TIE_MM, Posture, branch_joints, choose, set_by_the_tool, travel

_CACHE: dict = {}
_POSTURED: dict = {}


def postured(cell, target: str):
    """The cell with every station's configuration on the target handed down: the cell's own ([station.config]) where
    it names one, else the chosen posture's (none where nothing reaches and clears: the nearest-home solutions, which
    the proofs then refuse with their reasons). The region, the envelope, the scene and the programs read it from
    there; chosen once per cell and target."""
    return per_cell(_POSTURED, cell, (target,), lambda: _postured(cell, target))


def _postured(cell, target: str):
    if cell.robot is None or target not in cell.robot.arms or not stations_of(cell):
        return cell
    changed = tuple(
        replace(s, config={**s.config, target: posture_config(cell, target, s)}) for s in stations_of(cell)
    )
    return with_section(cell, stations=changed)


def station_plan(cell, target: str, station):
    """The station's taught arm poses and whether the program names each one's full configuration, in the posture
    chosen for it (codegen/kinds/station/region.py station_plan)."""
    return region_plan(postured(cell, target), target, station)


def check(cell, only: list[str] | None = None) -> list:
    """The envelope check of every target with an arm (of `only`, if given) in the postures chosen, each station's
    margins with the note of a posture chosen to clear the cell."""
    if cell.robot is None:
        return []
    out = []
    for target in [t for t in cell.targets if t in cell.robot.arms and (only is None or t in only)]:
        for envelope in envelope_check(postured(cell, target), [target]):
            stations = tuple(
                replace(m, posture=posture_note(cell, target, section_of(cell).station_by_id(m.station_id)))
                for m in envelope.stations
            )
            out.append(replace(envelope, stations=stations))
    return out


def posture_config(cell, target: str, station) -> dict:
    """The configuration per pose the station's program takes on the target: the cell's own ([station.config]) where
    it gives one, else the chosen posture's ({} where none reaches and clears: the nearest-home solutions, which the
    proofs then refuse with their reasons)."""
    given = station.config.get(target)
    if given:
        return given
    return _decided(cell, target, station)[0]


def posture_note(cell, target: str, station) -> str:
    """'' where the station is worked in the posture the controller takes from the home by itself (or the cell names
    it); else what was chosen and why, in the target's own form (generate's report)."""
    if station.config.get(target):
        return ""
    return _decided(cell, target, station)[1]


def _decided(cell, target: str, station) -> tuple[dict, str]:
    return per_cell(_CACHE, cell, (target, station.id), lambda: _chosen(cell, target, station))


def _chosen(cell, target: str, station) -> tuple[dict, str]:
    tried = candidates(cell, target, station)
    if not tried:
        return {}, ""
    natural = evaluate(cell, target, station, tried[0])
    if not natural.reaches:
        return {}, ""
    if natural.least_mm is not None and set_by_the_tool(cell.robot.arms[target], natural.nearest):
        return natural.config, ""
    best = choose(natural, tried[1:], lambda posture, bar: evaluate(cell, target, station, posture, bar, every=True))
    if best is None:
        return {}, ""
    if best is natural:
        return natural.config, ""
    return best.config, _note(cell, target, natural, best)


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
    too (before it replaces the nearest-home one; generate proves the one kept at every reading in any case)."""
    from codegen.world.proof import ClearanceError, prove  # coal: loaded only when proving

    tried = with_posture(cell, target, station, posture.config)
    moved = next(s for s in stations_of(tried) if s.id == station.id)
    try:
        station_margin(tried, target, moved)
    except ReachError as exc:
        return replace(posture, refusal=str(exc), reaches=False)
    try:
        paths = station_paths(tried, target, moved)
        least = prove(tried, paths[:1], bar)
        if every:
            prove(tried, paths[1:])
    except (ClearanceError, ValueError) as exc:
        return replace(posture, refusal=str(exc))
    nearest = min(least, key=lambda x: x.found.distance)
    return replace(posture, least_mm=nearest.found.distance, nearest=nearest)


def with_posture(cell, target: str, station, config: dict):
    """The cell with the station's configuration on the target given as config (the other stations as they are)."""
    changed = tuple(
        replace(s, config={**s.config, target: config}) if s.id == station.id else s for s in stations_of(cell)
    )
    return with_section(cell, stations=changed)
