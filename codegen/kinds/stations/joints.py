"""The joints a correct station program's moves end at: the reference's poses through each controller's rule."""

from __future__ import annotations

import numpy as np

from codegen.controllers import get_target
from codegen.kinds.stations.region import move_joints, station_plan
from codegen.reference import Move
from codegen.robot import solve

# Both sides solve the same inverse kinematics for poses that agree within verify's pose tolerance
# (float32: 0.005 mm, 0.001 deg). With the wrist at least the cell's wrist margin (5 deg) from its
# singularity, 0.001 deg of orientation moves axes 4 and 6 by at most 0.001 / sin(5 deg) = 0.012 deg;
# 0.005 mm moves a shoulder axis by far less. A different solution or turn differs by degrees.
JOINT_TOLERANCE_DEG = 0.05


def expected_joints(
    cell, target: str, station, moves: tuple[Move, ...], start: np.ndarray, solved=None
) -> list[np.ndarray]:
    """Per move of the reference: the joints the controller takes, by the rule the program's text
    sets for that pose (codegen/robot/region.py move_joints). solved: the analytic solutions per move
    when they are known already (the interpreter's, of a pose verify found equal to the reference's
    within its tolerance): the rule is then applied to them instead of solving again."""
    robot = cell.robot
    arm = robot.arms[target]
    form = get_target(target).configuration
    poses, named_poses = station_plan(cell, target, station)
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


def arm_problem(cell, target: str, expected, moves: tuple[Move, ...], got: list, home: np.ndarray) -> str | None:
    """The joints of every move against the controller's rule applied to the reference's poses, and
    the load the program set against the cell's tool."""
    station = expected.station
    want = [home]
    back = len(moves) > 1 and moves[-1] is moves[0]  # the way home after the station ([cell.motion])
    inner = moves[1:-1] if back else moves[1:]
    if station is not None and inner:
        want += expected_joints(cell, target, station, inner, home, [g.solutions for g in got[1 : 1 + len(inner)]])
    if back:
        want.append(home)
    tool = cell.robot.tool
    load = (tool.mass_kg, *tool.cog_mm) if cell.robot.tool_given else None
    for i, (g, e, q) in enumerate(zip(got, moves, want, strict=True)):
        where = f"move {i + 1} ({e.pose_name}, line {g.line})"
        if g.joints is None or np.isnan(q).any():
            return f"{where}: joints {g.joints}, expected {q}"
        error = float(np.max(np.abs(g.joints - q)))
        if not error <= JOINT_TOLERANCE_DEG:
            return (
                f"{where}: the arm ends at joints {_text(g.joints)}, the controller's rule gives {_text(q)} "
                f"({error:.3f} deg apart; tolerance {JOINT_TOLERANCE_DEG} deg)"
            )
        have = g.settings.get("load")
        if load is not None and (have is None or not _same_load(have, load)):
            return f"{where}: load {have}, expected the cell's tool (mass kg, centre of gravity mm) {load}"
    return None


def _same_load(have, want) -> bool:
    """Mass and centre of gravity equal to float32 rounding (1e-5 relative) or 0.001 (kg, mm)."""
    return len(have) == len(want) and all(abs(h - w) <= 1e-3 + 1e-5 * abs(w) for h, w in zip(have, want, strict=True))


def _text(q) -> str:
    return "[" + ", ".join(f"{v:.3f}" for v in q) + "]"
