"""The joints a correct program's moves end at: the reference's poses through each controller's rule."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from codegen.controllers import get_target
from codegen.model.robot import numbered_names
from codegen.poses import native_values
from codegen.reference import JOINT, Move
from codegen.robot import solve
from codegen.robot.envelope import singular_distance, wrist_angle
from codegen.robot.region import move_joints, per_cell, station_plan

# Both sides solve the same inverse kinematics for poses that agree within verify's pose tolerance
# (float32: 0.005 mm, 0.001 deg). With the wrist at least the cell's wrist margin (5 deg) from its
# singularity, 0.001 deg of orientation moves axes 4 and 6 by at most 0.001 / sin(5 deg) = 0.012 deg;
# 0.005 mm moves a shoulder axis by far less. A different solution or turn differs by degrees.
JOINT_TOLERANCE_DEG = 0.05

_HOME: dict = {}


def home_move(cell, target: str) -> tuple[Move, np.ndarray] | None:
    """The program's first motion, to the home joints, with the cell's tool; None without an arm."""
    robot = cell.robot
    if robot is None or target not in robot.arms:
        return None

    def compute():
        home = np.asarray(robot.home[target], dtype=float)
        return Move(JOINT, "home", robot.arms[target].kin.fk(home) @ robot.tool.tcp2flange, exact=True), home

    return per_cell(_HOME, cell, (target,), compute)


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


def tool_inputs(cell, target: str) -> dict:
    """The controller's numbered tool and load holding the cell's tool, where the program selects them
    (verify loads them as the controller's $config.dat holds them)."""
    robot = cell.robot
    number = None if robot is None else robot.tool.numbered.get(target)
    if number is None:
        return {}
    tool_name, load_name = numbered_names(target, number)
    tool = robot.tool
    tcp = tuple(native_values(tool.tcp, cell.pose_format, "xyzabc"))
    return {tool_name: tcp, load_name: (tool.mass_kg, *tool.cog_mm)}


def arm_of(cell, target: str):
    """The arm a target's program drives in verify (None: the cell names none; poses only)."""
    robot = cell.robot
    return None if robot is None else robot.arms.get(target)


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


class ArmStats:
    """The least joint-limit and wrist-singularity margins over every move verify saw."""

    def __init__(self) -> None:
        self.moves = 0
        self.joint_margin_deg = float("inf")
        self.wrist_margin_deg = float("inf")

    def add(self, cell, target: str, moves: list) -> None:
        arm = arm_of(cell, target)
        joints = [m.joints for m in moves if m.joints is not None]
        if arm is None or not joints:
            return
        joint, wrist = margins(arm, np.array(joints))
        self.moves += len(joints)
        self.joint_margin_deg = min(self.joint_margin_deg, joint)
        self.wrist_margin_deg = min(self.wrist_margin_deg, wrist)

    def merge(self, other: ArmStats) -> None:
        self.moves += other.moves
        self.joint_margin_deg = min(self.joint_margin_deg, other.joint_margin_deg)
        self.wrist_margin_deg = min(self.wrist_margin_deg, other.wrist_margin_deg)

    def summary(self) -> dict:
        return {
            "moves": self.moves,
            "joint_margin_deg": round(self.joint_margin_deg, 3),
            "wrist_margin_deg": round(self.wrist_margin_deg, 3),
        }


def require_margins(subject: str, robot, joint_deg: float, wrist_deg: float, worst: str) -> None:
    """ReachError unless the least joint and wrist margins over a program's poses meet the cell's."""
    need = robot.margins
    if joint_deg < need.joint_deg or wrist_deg < need.wrist_deg:
        from codegen.robot.taught import ReachError

        raise ReachError(
            f"{subject}: {joint_deg:.1f} deg to a joint limit ({worst}) and the wrist {wrist_deg:.1f} deg from its "
            f"singularity; the cell asks {need.joint_deg:g} and {need.wrist_deg:g} deg"
        )


@dataclass(frozen=True)
class Margins:
    """The least margins of a target's arm over the poses a program commands (a pallet's cycle, a
    conveyor's window); a subclass names what was checked (subject) and its own report keys (keys)."""

    target: str
    model: str
    joint_margin_deg: float
    wrist_margin_deg: float
    worst: str  # the pose with the least joint margin

    def subject(self) -> tuple[str, int, str]:
        """What was checked, how many poses, and what they are called."""
        raise NotImplementedError

    def keys(self) -> dict:
        raise NotImplementedError

    def text(self) -> str:
        what, count, noun = self.subject()
        return (
            f"{self.target} ({self.model}) {what}: {count} {noun} reachable; "
            f"{self.joint_margin_deg:.1f} deg to the nearest joint limit ({self.worst}), "
            f"wrist {self.wrist_margin_deg:.1f} deg from its singularity"
        )

    def as_json(self) -> dict:
        return {
            "target": self.target,
            "model": self.model,
            **self.keys(),
            "joint_margin_deg": self.joint_margin_deg,
            "wrist_margin_deg": self.wrist_margin_deg,
        }


def margins(arm, joints: np.ndarray) -> tuple[float, float]:
    """Degrees to the nearest joint limit and from the wrist singularity, for (..., 6) joints."""
    joint = np.minimum(joints - arm.limits[:, 0], arm.limits[:, 1] - joints)
    return float(np.min(joint)), float(np.min(singular_distance(wrist_angle(arm, joints))))
