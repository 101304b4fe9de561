"""Each taught pose's joints per target: from the configuration the cell gives, else nearest the home joints."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from codegen.protocol import get_kind
from codegen.robot import solve
from codegen.robot.config import FORMS

JOINTS_MATCH_DEG = 1.0  # taught joints must name a solution of the taught pose within this, per axis


class ReachError(Exception):
    """A taught pose the arm cannot take as the cell says; the message names station, pose and target."""


@dataclass(frozen=True)
class ArmPose:
    name: str
    motion: str  # "joint" or "linear"
    tcp2base: np.ndarray  # at calibration
    joints: np.ndarray  # deg, the taught configuration
    branch: int  # which analytic solution (the arm's configuration; codegen/robot/solve.py)


def configuration(form: str, arm, joints: np.ndarray) -> tuple:
    """What the program writes for these joints in the target's form (codegen/robot/config.py)."""
    return FORMS[form].of(arm, joints)


def select(form: str, arm, solutions: np.ndarray, value) -> tuple[np.ndarray, np.ndarray]:
    """The solution a configuration names, by the controller's rule: (joints, branch)."""
    return FORMS[form].select(arm, solutions, value)


def arm_poses(cell, target: str, station) -> list[ArmPose]:
    """The station's arm poses with their taught joints, in the order the program visits them."""
    robot = cell.robot
    arm, home = robot.arms[target], np.asarray(robot.home[target], dtype=float)
    given = station.config.get(target, {})
    poses = get_kind(station.kind).arm_poses(cell, station)
    flange2base = solve.flange_poses(np.array([p[1] for p in poses]), robot.tool.tcp2flange)
    solutions = solve.branches(arm, flange2base)
    out: list[ArmPose] = []
    previous = home
    for (name, tcp2base, motion), sols in zip(poses, solutions, strict=True):
        where = f"station {station.id} {station.name!r} pose {name!r} ({target}, {arm.model})"
        if np.isnan(sols).all():
            raise ReachError(f"{where}: out of reach (no inverse kinematics solution for the tool's flange)")
        config = given.get(name)
        if config is None:
            joints, branch = solve.nearest(arm, sols, previous if motion == "linear" else home)
            if np.isnan(joints).any():
                raise ReachError(f"{where}: no solution within the joint limits")
        elif config.form == "joints":
            joints, branch = solve.nearest(arm, sols, np.asarray(config.value))
            if np.isnan(joints).any() or np.max(np.abs(joints - config.value)) > JOINTS_MATCH_DEG:
                raise ReachError(
                    f"{where}: the taught joints {list(config.value)} do not reach this pose "
                    f"(nearest solution {np.round(joints, 2).tolist()})"
                )
        else:
            joints, branch = select(config.form, arm, sols, config.value)
            if np.isnan(joints).any():
                raise ReachError(f"{where}: the arm cannot take this pose in configuration {config.value}")
        joints = np.where(np.abs(joints) < solve.BOUNDARY_DEG, 0.0, joints)  # an axis at 0 is not negative
        out.append(ArmPose(name, motion, tcp2base, joints, int(branch)))
        previous = joints
    return out
