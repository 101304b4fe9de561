"""The joints a correct station program's moves end at: the reference's poses through each controller's rule."""

from __future__ import annotations

import numpy as np

from codegen.controllers import get_target
from codegen.kinds.station.plan import taught_poses
from codegen.kinds.station.region import move_joints
from codegen.reference import Move
from codegen.robot import solve


def expected_joints(
    cell, target: str, station, moves: tuple[Move, ...], start: np.ndarray, solved=None
) -> list[np.ndarray]:
    """Per move of the reference: the joints the controller takes, by the rule the program's text
    sets for that pose (codegen/kinds/station/region.py move_joints). solved: the analytic solutions per move
    when they are known already (the interpreter's, of a pose verify found equal to the reference's
    within its tolerance): the rule is then applied to them instead of solving again."""
    robot = cell.robot
    arm = robot.arms[target]
    form = get_target(target).configuration
    poses, named_poses = taught_poses(cell, target, station)
    taught = {}
    for pose, named in zip(poses, named_poses, strict=True):
        taught.setdefault(pose.name, (pose, named))
    out, previous = [], start
    solved = list(solved) if solved is not None else [None] * len(moves)
    missing = [i for i, s in enumerate(solved) if s is None]
    if missing:
        flanges = solve.flange_poses(np.array([moves[i].tcp2base for i in missing]), robot.tool.tcp2flange)
        for i, solutions in zip(missing, solve.branches(arm, flanges), strict=True):
            solved[i] = solutions
    for move, solutions in zip(moves, solved, strict=True):
        pose, named = taught[move.pose_name]
        q, _, _ = move_joints(arm, form, pose, solutions, previous, named)
        out.append(q)
        previous = q
    return out
