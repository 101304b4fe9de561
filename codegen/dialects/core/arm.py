"""The arm a program drives in the interpreter: the active tool, the joints after each move, the controller's rules."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from codegen.dialects.core.values import RunError
from codegen.robot import solve
from codegen.robot.arms import Arm
from codegen.robot.config import FORMS, ROUNDING_MARGIN_DEG, nearest_margin, with_status
from codegen.robot.margins import wrist_angle

# The tool active when a program starts is whatever the last program left (set by an instruction or a
# system variable; or named by each move): the interpreter assumes one that is not the flange, so a
# program that moves without setting its tool moves somewhere else in its trace.
ACTIVE_TOOL_AT_START = np.array(
    [[1.0, 0.0, 0.0, 12.0], [0.0, 1.0, 0.0, -7.0], [0.0, 0.0, 1.0, 95.0], [0.0, 0.0, 0.0, 1.0]]
)
ACTIVE_TOOL_AT_START.flags.writeable = False


@dataclass
class _Pending:
    event: object  # the MoveEvent whose joints (and, for a joint target, pose) the resolution fills
    where: str
    rule: str  # "joints" or a to_pose rule
    value: object = None  # joints (deg), robconf, (S, T) or S
    flange2base: np.ndarray | None = None
    tcp2flange: np.ndarray | None = None
    check: object = None  # the confdata a linear move must end in (the configuration check on)


class ArmState:
    """Tool and joints of one run. The moves are solved together when the run ends (one batched inverse
    kinematics for the run) or when the program asks for the current joints; until then each move is
    recorded with the rule its controller applies."""

    def __init__(self, arm: Arm | None) -> None:
        self.arm = arm
        self.tcp2flange = ACTIVE_TOOL_AT_START
        self.joints: np.ndarray | None = None
        self.branch = -1
        self.known = False  # a move so far fixed the joints (a joint target or a full configuration)
        self.pending: list[_Pending] = []
        self._bounds: list[tuple[float, float]] | None = None  # the limits with their slack (first check)

    def stand_at(self, q_deg) -> None:
        """The arm stands at these joints (deg) when the program starts."""
        self.joints = np.asarray(q_deg, dtype=float)

    def standing_pose(self) -> np.ndarray | None:
        """The active tool's TCP where the arm stood when the program started (base frame; None without the
        arm's model or its start joints): what a controller reads as the actual pose before the first move."""
        if self.arm is None or self.joints is None:
            return None
        return self.arm.kin.fk(self.joints) @ self.tcp2flange

    def from_start(self) -> None:
        """A controller that solves a first move to a pose from where the arm stands (UR: the solution nearest
        the joints, a linear move keeping their configuration), where the run knows them (--start): they count
        as the last move's (a language that needs a joint move first whatever the joints does not call this)."""
        if not self.known and self.arm is not None and self.joints is not None:
            self.branch = _joint_target(self.arm, self.joints)[1]
            self.known = True

    def actual(self, where: str) -> np.ndarray:
        """Where the arm's joints are now (deg): after the moves so far, or where it stood at the start."""
        self.resolve()
        if self.joints is None:
            raise RunError(f"{where}: the arm's joints are not known here (codegen run: --start J1,...,J6 in deg)")
        return self.joints

    def to_joints(self, event, q_deg, where: str) -> None:
        """A move to a joint position (MoveAbsJ, PTP to an AXIS, movej(q)); the pose is the forward
        kinematics with the active tool (without an arm: no pose, event.tcp2base stays None)."""
        q = np.asarray(q_deg, dtype=float)
        if self.arm is None:  # no kinematics: the move is known by its joints only
            event.joints = q
            return
        self.pending.append(_Pending(event, where, "joints", q, tcp2flange=self.tcp2flange))
        self.known = True

    def to_pose(self, event, where: str, rule: str, value=None, check=None) -> None:
        """A move to event.tcp2base by the controller's rule.

        rule: a configuration form of codegen/robot/config.py ("confdata", "status_turn"; value: the
        program's configuration), "status" (value: the status bits alone: the shortest turn), "nearest"
        (the solution nearest the current joints), "keep" (a linear move: the nearest, and the
        configuration must not change); check: the confdata a linear move must end in, when checked."""
        if self.arm is None:
            return
        if rule in ("nearest", "keep", "status") and not self.known:
            raise RunError(
                f"{where}: the first motion goes to a pose from wherever the arm stands; move to a joint "
                "position (or a pose with its full configuration) first"
            )
        flange2base = solve.flange_poses(event.tcp2base, self.tcp2flange)
        self.pending.append(_Pending(event, where, rule, value, flange2base, check=check))
        self.known = True

    def current(self, where: str) -> np.ndarray | None:
        """The joints after the moves so far (solving the pending ones)."""
        self.resolve()
        return self.joints

    def resolve(self) -> None:
        """Solve the pending moves in order: RunError at the first one the controller would refuse."""
        if not self.pending:
            return
        pending, self.pending = self.pending, []
        arm = self.arm
        poses = [p for p in pending if p.rule != "joints"]
        solutions = iter(solve.branches(arm, np.array([p.flange2base for p in poses])) if poses else ())
        for p in pending:
            if p.rule == "joints":  # the same joint targets (a home position) come back run after run
                flange2base, branch = _joint_target(arm, p.value)
                p.event.tcp2base = flange2base @ p.tcp2flange
                q = p.value
            else:
                p.event.solutions = next(solutions)
                q, branch = self._select(p, p.event.solutions)
            self._check_limits(q, p.where)
            self.joints, self.branch = q, branch
            p.event.joints = q

    def _select(self, p: _Pending, sols: np.ndarray) -> tuple[np.ndarray, int]:
        arm = self.arm
        if np.isnan(sols).all():
            raise RunError(f"{p.where}: the target is out of reach of the {arm.model}")
        if p.rule in FORMS:  # the move names the full configuration
            q, branch = FORMS[p.rule].select(arm, sols, p.value)
            if np.isnan(q).any():
                raise RunError(f"{p.where}: the {arm.model} cannot reach this pose in configuration {list(p.value)}")
        elif p.rule == "status":
            candidates = with_status(arm, sols, p.value)
            q, branch = solve.nearest(arm, candidates, self.joints)
            if np.isnan(q).any():
                raise RunError(f"{p.where}: the {arm.model} cannot reach this pose with S {p.value}")
            self._decided(p, candidates, q)
        else:
            q, branch = solve.nearest(arm, sols, self.joints)
            if np.isnan(q).any():
                raise RunError(f"{p.where}: no solution within the joint limits of the {arm.model}")
            if p.rule == "nearest":
                self._decided(p, sols, q)
            if p.rule == "keep" and branch != self.branch:
                raise RunError(
                    f"{p.where}: a linear move would change the arm's configuration: {_flip(arm, self.joints, q)} "
                    f"(from joints {_text(self.joints)} to {_text(q)}); the controller stops. Reach the pose with "
                    "a joint move first, or turn the tool so that the path keeps the wrist on one side"
                )
        if p.check is not None:
            have = FORMS["confdata"].of(arm, q)
            if tuple(have) != tuple(p.check):
                raise RunError(
                    f"{p.where}: the linear move ends in configuration {list(have)}, not the programmed "
                    f"{list(p.check)} (configuration check on: the controller stops)"
                )
        return q, int(branch)

    def _decided(self, p: _Pending, candidates: np.ndarray, q: np.ndarray) -> None:
        """A joint move to the solution nearest where the arm stands (the controller's closest configuration or
        shortest turn) must have one: with two equally near (an axis half a turn away either way, or two
        branches), which one the controller takes is decided by its rounding: RunError."""
        margin, axis = nearest_margin(self.arm, candidates, self.joints)
        if margin < ROUNDING_MARGIN_DEG:
            what = f"axis {axis + 1} half a turn away either way" if axis >= 0 else "two configurations"
            raise RunError(
                f"{p.where}: from joints {_text(self.joints)} the nearest solution is not unique ({what}, "
                f"{margin:.2g} deg apart): the controller's choice is decided by rounding; name the "
                "configuration or move to a joint position first"
            )

    def _check_limits(self, q: np.ndarray, where: str) -> None:
        bounds = self._bounds
        if bounds is None:  # six Python floats a side: compared one by one faster than numpy's small arrays
            low, high = self.arm.limits[:, 0], self.arm.limits[:, 1]
            bounds = self._bounds = list(zip((low - 1e-6).tolist(), (high + 1e-6).tolist(), strict=True))
        for i, (v, (below, above)) in enumerate(zip(q.tolist(), bounds, strict=True)):
            if v < below or v > above:  # the first axis outside (a NaN is not: as numpy's comparisons)
                low, high = self.arm.limits[:, 0], self.arm.limits[:, 1]
                raise RunError(
                    f"{where}: axis {i + 1} at {q[i]:.3f} deg is beyond its limits [{low[i]:g}, {high[i]:g}] "
                    f"of the {self.arm.model}"
                )


_TARGETS: dict = {}


def _joint_target(arm: Arm, q: np.ndarray) -> tuple[np.ndarray, int]:
    """flange2base of a joint position and its branch (the analytic solution it is), remembered."""
    key = (id(arm), q.tobytes())
    hit = _TARGETS.get(key)
    if hit is None or hit[0] is not arm:
        flange2base = arm.kin.fk(q)
        _, branch = solve.nearest(arm, solve.branches(arm, flange2base), q)
        if len(_TARGETS) > 4096:
            _TARGETS.clear()
        hit = _TARGETS[key] = (arm, flange2base, int(branch))
    return hit[1], hit[2]


def remember_joint_target(arm: Arm, q: np.ndarray, branch: int) -> None:
    """A joint position the program computed by inverse kinematics (UR get_inverse_kin): its branch is
    known, so the move to it needs only the forward kinematics."""
    if len(_TARGETS) > 4096:
        _TARGETS.clear()
    _TARGETS[(id(arm), q.tobytes())] = (arm, arm.kin.fk(q), int(branch))


def _flip(arm: Arm, q0: np.ndarray, q1: np.ndarray) -> str:
    """Which joint makes the configuration change: the wrist axis through its singular angle, else the axis that
    turns the most, with its values."""
    w0, w1 = (float(wrist_angle(arm, np.asarray(q))) for q in (q0, q1))
    if math.floor(w0 / 180.0) != math.floor(w1 / 180.0):  # through a multiple of 180 deg: the wrist flips
        return f"axis 5 passes its singular angle (the wrist flips: from {q0[4]:.1f} to {q1[4]:.1f} deg)"
    k = int(np.argmax(np.abs(np.asarray(q1) - np.asarray(q0))))
    return f"axis {k + 1} turns from {q0[k]:.1f} to {q1[k]:.1f} deg (a shoulder or elbow flip)"


def _text(q: np.ndarray) -> str:
    return "[" + ", ".join(f"{v:.2f}" for v in q) + "]"
