"""The pick program proven reachable at generate time: the whole window, across the belt and at every part height."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from codegen.controllers import get_target
from codegen.kinds.conveyor.section import conveyor_of
from codegen.kinds.conveyor.timing import descent_seconds
from codegen.poses import rotmat_from_zyx_deg
from codegen.robot import solve
from codegen.robot.expect import Margins, margins, require_margins
from codegen.robot.taught import ReachError

STEPS = 12  # poses along the window per line the gripper follows


@dataclass(frozen=True)
class ConveyorReach(Margins):
    """The conveyor's window on one target's arm: the least margins over the poses it may take there."""

    poses: int = 0

    def subject(self) -> tuple[str, int, str]:
        return "conveyor window", self.poses, "poses"

    def keys(self) -> dict:
        return {"poses": self.poses}


def follow_mm(cell, target: str) -> float:
    """How far past the window's end a tracking arm may still follow the part: the belt at its fastest for the
    gripper's timeout twice (the grip; after a grip not confirmed, the wait for the gripper to read open, which a
    program may make before it leaves the belt) and the longer lift (the part held: lift_dz, its bottom to the clear
    height; none held: from the lowest part's top to the clear height), at the work speed with the program's path
    acceleration's ramps, where the target's program sets one: descent_seconds; an intercepting arm does not
    follow: 0)."""
    pick = conveyor_of(cell).pick
    if pick.tracking[target] != "native":
        return 0.0
    lift = max(pick.lift_dz, pick.clear_mm - pick.z_range_mm[0])
    timeout = cell.io.timeout_s if cell.io is not None else 0.0
    seconds = 2.0 * timeout + descent_seconds(cell, get_target(target), lift)
    return pick.belt_speed_max_mm_s * seconds


def lines(cell, beyond_mm: float = 0.0) -> list[tuple[str, list[np.ndarray]]]:
    """The paths the gripper follows relative to the belt, as base-frame poses (4x4): at each corner of
    the ranges across the belt and in height, on the part, above it and lifted with it, from the window's start to its
    end and beyond_mm past it (the arm follows the part along them); then the place and above it."""
    conveyor, pick = conveyor_of(cell), conveyor_of(cell).pick
    frame = conveyor.frame()
    grip = np.eye(4)
    grip[:3, :3] = rotmat_from_zyx_deg(*pick.tool_orientation)
    out = []
    for x in pick.x_range_mm:
        for z in pick.z_range_mm:
            on = -pick.overtravel_mm  # the suction cup pressed on
            for dz, what in ((pick.approach_dz, "above the part"), (on, "on the part"), (pick.lift_dz, "lifted")):
                path = []
                for y in np.linspace(pick.window_mm[0], pick.window_mm[1] + beyond_mm, STEPS):
                    place = np.eye(4)
                    place[:3, 3] = (x, y, z + dz)
                    path.append(frame @ place @ grip)
                out.append((f"{what} at x {x:g} z {z:g} mm", path))
    above = pick.place.matrix().copy()
    above[2, 3] += pick.approach_dz
    out.append(("the place", [above, pick.place.matrix()]))
    return out


def check(cell, only: list[str] | None = None) -> list[ConveyorReach]:
    """Each line from home by the nearest solution, keeping one configuration along it (the arm follows
    the belt in straight moves), every pose within the cell's margins; ReachError names the pose."""
    conveyor = conveyor_of(cell)
    if conveyor is None or conveyor.pick is None or cell.robot is None:
        return []
    out = []
    for target in conveyor.pick.tracking:
        if target not in cell.robot.arms or (only is not None and target not in only):
            continue
        robot, arm = cell.robot, cell.robot.arms[target]
        worst_joint, worst_wrist, worst, wrist_pose, count = np.inf, np.inf, "", "", 0
        for what, path in lines(cell, follow_mm(cell, target)):
            poses = solve.flange_poses(np.array(path), robot.tool.tcp2flange)
            q, branch = np.asarray(robot.home[target], dtype=float), None
            for i, sols in enumerate(solve.branches(arm, poses)):
                joints, chosen = solve.nearest(arm, sols, q)
                at = f"conveyor ({target}, {arm.model}): {what}, pose {i + 1} of {len(path)}"
                if np.isnan(joints).any():
                    raise ReachError(f"{at}: out of reach")
                if branch is not None and int(chosen) != branch:
                    raise ReachError(f"{at}: the arm would change its configuration while it follows the belt")
                q, branch = joints, int(chosen)
                joint, wrist = margins(arm, joints)
                if joint < worst_joint:
                    worst_joint, worst = joint, what
                if wrist < worst_wrist:
                    worst_wrist, wrist_pose = wrist, what
                count += 1
        require_margins(f"conveyor ({target}, {arm.model})", robot, worst_joint, worst_wrist, worst, wrist_pose)
        out.append(ConveyorReach(target, arm.model, worst_joint, worst_wrist, worst, wrist_pose, poses=count))
    return out
