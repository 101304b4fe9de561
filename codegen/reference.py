"""The expected trace of a correct program: what every kind's float64 reference produces."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from codegen.model.motion import segments
from codegen.poses import concat

JOINT = "joint"
LINEAR = "linear"


@dataclass(frozen=True, kw_only=True)
class Move:
    kind: str  # JOINT or LINEAR
    pose_name: str
    tcp2base: np.ndarray = field(compare=False)
    exact: bool = False  # the arm must stop at this pose (a work or photo pose): no blending
    speed_mm_s: float | None = None  # the programmed TCP speed ([cell.motion]); None: the target's facts
    zone_mm: float = 0.0  # the blending zone ([cell.motion]); 0: the arm stops at the pose
    joint_percent: float | None = None  # a joint move's axis speed in percent ([cell.motion]), where programmed so


def path_moves(cell, station, correction: np.ndarray, fixed: frozenset[str] = frozenset()) -> list[Move]:
    """The moves through a station's path (its taught poses, then the retreat) with each pose moved by
    the correction (a taught pose P becomes correction . P; a `fixed` one stays as taught), and each segment's
    speed and zone (a stop where the gripper acts)."""
    segs = segments(cell.motion, len(station.poses), station.retreat is not None, station_stops(station))
    return [
        Move(
            kind=JOINT if i == 0 else LINEAR,
            pose_name=p.name,
            tcp2base=p.matrix() if p.name in fixed else concat(p.matrix(), correction),
            exact=s.exact,
            speed_mm_s=s.speed_mm_s,
            zone_mm=s.zone_mm,
            joint_percent=cell.motion.joint_speed_percent if i == 0 else None,
        )
        for i, (p, s) in enumerate(zip(station.path, segs, strict=True))
    ]


def station_stops(station) -> frozenset[int]:
    """The indices of a station's taught poses where its gripper acts (the arm stops there)."""
    acting = {name for name, _ in station.gripper}
    return frozenset(i for i, p in enumerate(station.poses) if p.name in acting)


@dataclass(frozen=True)
class ExpectedTrace:
    """Expected behaviour of a correct program for one case."""

    status: str  # "ok" or "halt"
    reason: str | None = None  # a codegen.guard halt reason
    station: Any = None  # codegen.model.cell.Station, or None for an unknown station
    moves: tuple[Move, ...] = ()
    logged: tuple[float, ...] | None = None  # the numbers of the program's log line(s), in order
    detail: Any = None  # the kind's own figures (kinds/<kind>.py), e.g. the correction or the photos
    path_start: int = 0  # where the station's path (its taught poses, then the retreat) begins in `moves`


def home_move(cell, target: str) -> tuple[Move, np.ndarray] | None:
    """The program's first motion, to the home joints, with the cell's tool, and the home joints; None without an arm.
    Worked out once per cell and target and kept with the cell (Cell.plans, as the kinds' plans are): verify asks for
    it in every case, and no store outlives its cell."""
    robot = cell.robot
    if robot is None or target not in robot.arms:
        return None
    key = ("home", target)
    if key not in cell.plans:
        home = np.asarray(robot.home[target], dtype=float)
        tcp2base = robot.arms[target].kin.fk(home) @ robot.tool.tcp2flange
        cell.plans[key] = Move(kind=JOINT, pose_name="home", tcp2base=tcp2base, exact=True), home
    return cell.plans[key]
