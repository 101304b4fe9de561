"""The joints a correct program's moves end at: the reference's poses through each controller's rule."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from codegen.robot.margins import joint_margins, least_joint_margin, singular_distance, wrist_angle
from codegen.robot.taught import ReachError

# Both sides solve the same inverse kinematics for poses that agree within the pose tolerance (float32:
# 0.005 mm, 0.001 deg). With the wrist at least the cell's wrist margin (5 deg) from its singularity, 0.001 deg
# of orientation moves axes 4 and 6 by at most 0.001 / sin(5 deg) = 0.012 deg; 0.005 mm moves a shoulder axis
# by far less. A different solution or turn differs by degrees. Two joint margins this close are one margin: generate
# (the reference's joints) and verify (the interpreter's) could order them either way, so each names the first in
# its order among them (the moves in the order the kind plans them).
JOINT_TOLERANCE_DEG = 0.05


def arm_of(cell, target: str):
    """The arm a target's program drives in verify (None: the cell names none; poses only)."""
    robot = cell.robot
    return None if robot is None else robot.arms.get(target)


class _Named:
    """The place to name for a least margin: the first, in the cases' order, within JOINT_TOLERANCE_DEG of the least.
    Kept as the places that were the least so far in that order (a later place can be named only where it is less
    than every earlier one), those beyond the tolerance of the least dropped: parts merged in the cases' order name
    the same place however the cases were split among them."""

    def __init__(self) -> None:
        self.records: list[tuple[float, str]] = []  # (margin, place), margins falling

    def add(self, margins: np.ndarray, place: Callable[[int], str]) -> None:
        """A run's margins in its moves' order; place(i): the text naming move i (asked only for a record)."""
        least = self.records[-1][0] if self.records else float("inf")
        for i in np.flatnonzero(margins < np.minimum.accumulate(np.concatenate(([least], margins)))[:-1]):
            self.records.append((float(margins[i]), place(int(i))))
        self._prune()

    def merge(self, other: _Named) -> None:
        """A later part's places."""
        for margin, place in other.records:
            if not self.records or margin < self.records[-1][0]:
                self.records.append((margin, place))
        self._prune()

    def _prune(self) -> None:
        if self.records:
            least = self.records[-1][0]
            self.records = [r for r in self.records if r[0] <= least + JOINT_TOLERANCE_DEG]

    @property
    def place(self) -> str:
        return self.records[0][1] if self.records else ""


class ArmStats:
    """The least joint-limit and wrist-singularity margins over every move verify saw."""

    def __init__(self) -> None:
        self.moves = 0
        self.joint_margin_deg = float("inf")
        self.wrist_margin_deg = float("inf")
        self.joint_named = _Named()  # the axis, its value, the move and the case of the least joint margin
        self.asked_deg = 0.0  # the cell's joint margin (cell.robot.joint_margin_deg): every move's requirement
        self.wrist_named = _Named()  # axis 5's value, the move and the case nearest the wrist singularity
        self.wrist_asked_deg = 0.0  # the cell's wrist margin (cell.robot.wrist_margin_deg)

    @property
    def joint_margin_at(self) -> str:
        return self.joint_named.place

    @property
    def wrist_margin_at(self) -> str:
        return self.wrist_named.place

    def add(
        self, cell, target: str, moves: list, case: Callable[[], str] | None = None, names: list | None = None
    ) -> None:
        """A run's moves; case: what the report calls the run (its category and scenario), asked only where the
        run holds the least joint margin so far; names: the expected moves' names, in the run's order (e.g. "layer
        2 box 3 transit"). Of the margins within JOINT_TOLERANCE_DEG of the least, the first in the cases' order is
        named (_Named)."""
        arm = arm_of(cell, target)
        solved = [(i, m) for i, m in enumerate(moves) if m.joints is not None]
        if arm is None or not solved:
            return
        self.asked_deg = cell.robot.margins.joint_deg
        self.wrist_asked_deg = cell.robot.margins.wrist_deg
        joints = np.array([m.joints for _i, m in solved])
        margins = joint_margins(arm, joints)
        per_move, axes = margins.min(axis=-1), margins.argmin(axis=-1)
        joint = float(per_move.min())
        wrists = np.atleast_1d(singular_distance(wrist_angle(arm, joints)))
        wrist = float(np.min(wrists))
        self.moves += len(solved)
        named = None

        def where(row: int, axis: int) -> str:
            nonlocal named
            if named is None:  # the case's name asked once, where a margin is the least so far
                named = " ".join(case().split()) if case is not None else ""
            index, move = solved[row]
            what = f": {names[index]}" if names is not None and index < len(names) else ""
            at = f"axis {axis + 1} at {joints[row, axis]:.1f} deg, move {index + 1} (line {move.line}{what})"
            return at + (f", {named}" if named else "")

        self.joint_named.add(per_move, lambda i: where(i, int(axes[i])))
        self.wrist_named.add(wrists, lambda i: where(i, 4))
        self.joint_margin_deg = min(self.joint_margin_deg, joint)
        self.wrist_margin_deg = min(self.wrist_margin_deg, wrist)

    def merge(self, other: ArmStats) -> None:
        """A later part's figures (the parts merged in the cases' order)."""
        self.moves += other.moves
        self.asked_deg = max(self.asked_deg, other.asked_deg)
        self.wrist_asked_deg = max(self.wrist_asked_deg, other.wrist_asked_deg)
        self.joint_named.merge(other.joint_named)
        self.wrist_named.merge(other.wrist_named)
        self.joint_margin_deg = min(self.joint_margin_deg, other.joint_margin_deg)
        self.wrist_margin_deg = min(self.wrist_margin_deg, other.wrist_margin_deg)

    def summary(self) -> dict:
        return {
            "moves": self.moves,
            "joint_margin_deg": round(self.joint_margin_deg, 3),
            "joint_margin_at": self.joint_margin_at,
            "wrist_margin_deg": round(self.wrist_margin_deg, 3),
            "joint_margin_asked_deg": self.asked_deg,
            "wrist_margin_at": self.wrist_margin_at,
            "wrist_margin_asked_deg": self.wrist_asked_deg,
        }

    def shortfall(self) -> str | None:
        """Where a run came nearer a joint limit than the cell asks: the margin, the axis, the move and the case, and
        the margin asked (None: every run kept it)."""
        if not self.moves or self.joint_margin_deg >= self.asked_deg:
            return None
        return (
            f"{self.joint_margin_deg:.1f} deg to a joint limit ({self.joint_margin_at}), less than the "
            f"{self.asked_deg:g} deg the cell asks (cell.robot.joint_margin_deg)"
        )

    def wrist_shortfall(self) -> str | None:
        """Where a run came nearer the wrist singularity than the cell asks: the margin, axis 5, the move and the
        case, and the margin asked (None: every run kept it)."""
        if not self.moves or self.wrist_margin_deg >= self.wrist_asked_deg:
            return None
        return (
            f"{self.wrist_margin_deg:.1f} deg from the wrist singularity ({self.wrist_margin_at}), less than the "
            f"{self.wrist_asked_deg:g} deg the cell asks (cell.robot.wrist_margin_deg)"
        )


# what a pose at the wrist singularity is, for a refusal's fix
WRIST_SINGULAR = "axis 5 near 0 deg lines up axes 4 and 6 (the tool in line with the forearm)"


def require_margins(
    subject: str, robot, joint_deg: float, wrist_deg: float, worst: str, wrist_pose: str = "", wrist_fix: str = ""
) -> None:
    """ReachError unless the least joint and wrist margins over a program's poses meet the cell's (worst: the pose
    of the least joint margin; wrist_pose: the pose nearest the wrist singularity; wrist_fix: what the caller's keys
    change to keep the wrist away from it, said where the wrist is too near)."""
    need = robot.margins
    if joint_deg < need.joint_deg or wrist_deg < need.wrist_deg:
        raise ReachError(
            f"{subject}: {joint_deg:.1f} deg to a joint limit ({worst}) and the wrist {wrist_deg:.1f} deg from its "
            f"singularity; the cell asks {need.joint_deg:g} and {need.wrist_deg:g} deg"
            + (f" (the wrist nearest its singularity: {wrist_pose})" if wrist_pose else "")
            + (f": {WRIST_SINGULAR}; {wrist_fix}" if wrist_fix and wrist_deg < need.wrist_deg else "")
        )


@dataclass(frozen=True)
class Margins:
    """The least margins of a target's arm over the poses a program commands (a kind's whole cycle or
    window); a subclass names what was checked (subject) and its own report keys (keys)."""

    target: str
    model: str
    joint_margin_deg: float
    wrist_margin_deg: float
    worst: str  # the pose with the least joint margin
    wrist_pose: str = ""  # the pose nearest the wrist singularity

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
            f"wrist {self.wrist_margin_deg:.1f} deg from its singularity (pose {self.wrist_pose})"
        )

    def as_json(self) -> dict:
        return {
            "target": self.target,
            "model": self.model,
            **self.keys(),
            "joint_margin_deg": self.joint_margin_deg,
            "wrist_margin_deg": self.wrist_margin_deg,
            "wrist_pose": self.wrist_pose,
        }


def margins(arm, joints: np.ndarray) -> tuple[float, float]:
    """Degrees to the nearest joint limit and from the wrist singularity, for (..., 6) joints."""
    return least_joint_margin(arm, joints)[0], float(np.min(singular_distance(wrist_angle(arm, joints))))


@dataclass(frozen=True)
class HomeMargin:
    """Where a target's arm starts and ends every program: its margins there (codegen.robot.margins' rule)."""

    target: str
    model: str
    home: tuple[float, ...]
    joint_margin_deg: float
    joint_axis: int  # 1-based
    wrist_margin_deg: float

    def text(self) -> str:
        return (
            f"home {self.target} ({self.model}): {self.joint_margin_deg:.1f} deg to the nearest joint limit (axis "
            f"{self.joint_axis} at {self.home[self.joint_axis - 1]:g} deg), wrist {self.wrist_margin_deg:.1f} deg "
            "from its singularity"
        )

    def as_json(self) -> dict:
        return {
            "target": self.target,
            "arm": self.model,
            "home": list(self.home),
            "joint_margin_deg": round(self.joint_margin_deg, 3),
            "joint_axis": self.joint_axis,
            "wrist_margin_deg": round(self.wrist_margin_deg, 3),
        }


def home_margins(cell, targets: list[str] | None = None) -> list[HomeMargin]:
    """Each requested target's home margins (targets without an arm have none)."""
    robot = cell.robot
    if robot is None:
        return []
    out = []
    for target in targets or cell.targets:
        arm = robot.arms.get(target)
        if arm is None:
            continue
        home = tuple(float(v) for v in robot.home[target])
        joint, (axis,) = least_joint_margin(arm, home)
        wrist = float(singular_distance(wrist_angle(arm, np.array(home))))
        out.append(HomeMargin(target, arm.model, home, joint, axis + 1, wrist))
    return out
