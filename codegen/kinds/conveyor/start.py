"""The pick program's start as verify expects it: where the arm starts, the way home, a part held put down first."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from codegen.kinds.conveyor.plan import AWAY, HOME, PUT_DOWN, carried, planned
from codegen.kinds.conveyor.program import safe_belt
from codegen.kinds.conveyor.section import conveyor_of
from codegen.poses import rotmat_from_zyx_deg
from codegen.robot import solve
from codegen.verify.plan import START_AWAY_DEG

HELD_AT = (0.5, 0.5)  # a stop mid-cycle: above a part this far into x_range_mm and the window, holding it


def grip_pose(cell, x: float, y: float, z: float) -> np.ndarray:
    """The gripper at (x, y, z) in the belt frame in its orientation on a part (base frame, 4x4)."""
    pick = conveyor_of(cell).pick
    place = np.eye(4)
    place[:3, :3] = rotmat_from_zyx_deg(*pick.tool_orientation)
    place[:3, 3] = (x, y, z)
    return conveyor_of(cell).frame() @ place


def start_joints(cell, target: str, start: str) -> np.ndarray | None:
    """Where the arm stands when the program starts: home; away (home and START_AWAY_DEG); mid-cycle (above a
    part on the belt after its lift, where a stop after the grip leaves it)."""
    robot = cell.robot
    if robot is None or target not in robot.arms:
        return None
    home = np.asarray(robot.home[target], dtype=float)
    if start == "away":
        return home + np.array(START_AWAY_DEG)
    if start == "mid_cycle":
        pick = conveyor_of(cell).pick
        (x0, x1), (y0, y1), (_z0, z1) = pick.x_range_mm, pick.window_mm, pick.z_range_mm
        pose = grip_pose(cell, x0 + HELD_AT[0] * (x1 - x0), y0 + HELD_AT[1] * (y1 - y0), z1 + pick.approach_dz)
        arm = robot.arms[target]
        joints, _ = solve.nearest(arm, solve.branches(arm, solve.flange_poses(pose, robot.tool.tcp2flange)), home)
        return joints
    return home


def first_moves(cell, target, start: str, held: bool) -> tuple[list, int | None]:
    """The moves before the first part's (the way home from away, home, a part held put down at the place) and
    after which of them the gripper opens at the start (None: it holds a part the program cannot put down)."""
    robot = cell.robot
    if robot is None or target.name not in robot.arms:
        return [], 0
    arm, tool = robot.arms[target.name], robot.tool.tcp2flange
    pick = conveyor_of(cell).pick
    home = np.asarray(robot.home[target.name], dtype=float)
    out = []
    if start != "home":
        here = start_joints(cell, target.name, start)
        stands = arm.kin.fk(here) @ tool
        back = stands @ _along_z(-pick.approach_dz)
        safe = grip_pose(cell, *safe_belt(cell))
        for segment, pose, joints in zip(AWAY, (stands, back, safe), (here, None, None), strict=True):
            out.append(_held(planned(segment, cell, target, pose=pose, joints=joints), cell, held))
    out.append(_held(planned(HOME, cell, target, pose=arm.kin.fk(home) @ tool, joints=home), cell, held))
    if not held:
        return out, len(out)
    place = pick.place.matrix()
    above = place.copy()
    above[2, 3] += pick.approach_dz
    for segment, pose in zip(PUT_DOWN, (above, place, above), strict=True):
        out.append(planned(segment, cell, target, pose=pose))
    return out, len(out) - 1


def _held(move, cell, held: bool):
    """A move of the way home while the gripper holds a part: the part's payload in force."""
    if not held or not cell.robot.tool_given:
        return move
    return replace(move, payload=carried(cell))


def _along_z(dz: float) -> np.ndarray:
    out = np.eye(4)
    out[2, 3] = dz
    return out
