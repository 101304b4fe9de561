"""The laser TCP program proven reachable at generate time: both circles and the tip search, within offset_max."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from codegen.kinds.laser.program import DOWN, circle_points, safe_point
from codegen.kinds.laser.section import laser_of
from codegen.robot import solve
from codegen.robot.expect import Margins, margins, require_margins
from codegen.robot.taught import ReachError

CIRCLE_STEPS = 24  # poses per circle


@dataclass(frozen=True)
class LaserReach(Margins):
    """The calibration's poses on one target's arm: the least margins over them."""

    poses: int = 0

    def subject(self) -> tuple[str, int, str]:
        return "laser station", self.poses, "poses"

    def keys(self) -> dict:
        return {"poses": self.poses}


def path(cell) -> list[tuple[str, np.ndarray]]:
    """The TCP's poses in the order the program takes them (base frame): the safe pose, each circle from above,
    around and back up; the search line from clearance above to clearance below the plane, with the axis found
    anywhere within offset_max_mm of S's origin (the four corners); the safe pose again (the way out)."""
    laser = laser_of(cell)
    sensor2base = laser.sensor_frame.matrix()
    rot = DOWN @ cell.robot.tool.tcp2flange[:3, :3]

    def pose(point) -> np.ndarray:
        out = np.eye(4)
        out[:3, :3] = rot
        out[:3, 3] = point
        return sensor2base @ out

    out = [("the safe pose", pose(safe_point(laser)))]
    for k in (0, 1):
        points = circle_points(laser, k)
        start = np.array(points["start"])
        radius, angle0, z = laser.circle_mm, math.pi / 4, start[2]
        out.append((f"above circle {k + 1}", pose(points["above"])))
        for i in range(CIRCLE_STEPS + 1):
            a = angle0 + 2 * math.pi * i / CIRCLE_STEPS
            out.append((f"circle {k + 1}", pose((radius * math.cos(a), radius * math.sin(a), z))))
        out.append((f"above circle {k + 1}", pose(points["above"])))
    m = laser.offset_max_mm
    for dx, dy in ((m, m), (-m, m), (-m, -m), (m, -m)):
        out.append(("the tip search's top", pose((dx, dy, laser.clearance_mm))))
        out.append(("the tip search's bottom", pose((dx, dy, -laser.clearance_mm))))
    out.append(("the safe pose", pose(safe_point(laser))))
    return out


def check(cell, only: list[str] | None = None) -> list[LaserReach]:
    """From home by the nearest solution, one configuration throughout (the moves near the sensors are
    straight or circular), every pose within the cell's margins; ReachError names the pose."""
    if laser_of(cell) is None or cell.robot is None:
        return []
    out = []
    poses = path(cell)
    for target, arm in cell.robot.arms.items():
        if only is not None and target not in only:
            continue
        robot = cell.robot
        flange = solve.flange_poses(np.array([p for _w, p in poses]), robot.tool.tcp2flange)
        q, branch = np.asarray(robot.home[target], dtype=float), None
        worst_joint, worst_wrist, worst, wrist_pose = np.inf, np.inf, "", ""
        for (what, _p), sols in zip(poses, solve.branches(arm, flange), strict=True):
            joints, chosen = solve.nearest(arm, sols, q)
            at = f"laser station ({target}, {arm.model}): {what}"
            if np.isnan(joints).any():
                raise ReachError(f"{at}: out of reach")
            if branch is not None and int(chosen) != branch:
                raise ReachError(f"{at}: the arm would change its configuration during the calibration")
            q, branch = joints, int(chosen)
            joint, wrist = margins(arm, joints)
            if joint < worst_joint:
                worst_joint, worst = joint, what
            if wrist < worst_wrist:
                worst_wrist, wrist_pose = wrist, what
        subject = f"laser station ({target}, {arm.model})"
        require_margins(subject, robot, worst_joint, worst_wrist, worst, wrist_pose)
        out.append(LaserReach(target, arm.model, worst_joint, worst_wrist, worst, wrist_pose, poses=len(poses)))
    return out
