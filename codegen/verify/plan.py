"""What verify expects of a run, in the same terms for every kind: planned moves, outputs, stored data, a stop."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from codegen.controllers import numbered_names
from codegen.dialects.core.machine import DEFAULT_STEP_LIMIT
from codegen.emit import Emitter
from codegen.guard import NOT_AT_HOME, halt_message
from codegen.poses import native_values
from codegen.world import loads

START_AWAY_DEG = (25.0, -15.0, 10.0, 0.0, 0.0, 0.0)  # the arm left away from home (the start_away scenario)
TOOL_LOAD = "tool"  # a planned move's payload: the cell's tool alone ([cell.tool] mass and centre of gravity)

# The scenarios every kind runs, or declares (VerifyPlan.scenarios) with the reason it cannot apply.
SCENARIOS = {
    "start_away": "the program started with the arm away from home",
    "start_mid_cycle": "the program started again where a stopped cycle left the arm (a stop and a restart)",
    "gripper_silent": "the gripper never confirms that it closed",
    "gripper_stuck": "the gripper never confirms that it opened",
    "device_late": "the kind's device (vision PC, belt queue, sensors) answers late, within its timeout",
    "device_silent": "the kind's device never answers",
    "reading_out_of_range": "the kind's device reports a value outside the range the program accepts",
}


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
    load = loads.of_tool(tool, robot.tool_shaped).principal_zyx()  # the numbered load's form: M, CM, J
    return {tool_name: tcp, load_name: tuple(load[k] for k in ("M", "X", "Y", "Z", "A", "B", "C", "JX", "JY", "JZ"))}


@dataclass(frozen=True)
class Case:
    """One run of a program: the report's category, the scenario it belongs to (SCENARIOS or the kind's own),
    where the arm starts ("home", "away", or a named pose the kind knows) and the kind's own data."""

    category: str
    data: Any = None
    scenario: str = "nominal"
    start: str = "home"


@dataclass
class Setup:
    """How a case runs: the keyword arguments of Program.run (inputs, devices, signals, start joints, the names
    kept at the end, the step limit, the controller's input cycle)."""

    inputs: dict = field(default_factory=dict)
    devices: tuple = ()
    signals: dict = field(default_factory=dict)
    start_joints: Any = None
    keep: tuple[str, ...] = ()
    step_limit: int | None = None
    signal_cycle_s: float | None = None
    # the case ends in the controller's error naming this (a name the installation lacks): the run's error is the
    # kind's to judge, with what ran until then; None: an error is a mismatch
    error: str | None = None

    def run_options(self, arm, step_limit: int | None) -> dict:
        """Program.run's keywords; the step limit asked (verify --step-limit) wins over the kind's own."""
        options = {
            "devices": self.devices,
            "signals": self.signals,
            "start_joints": self.start_joints,
            "keep": self.keep,
            "step_limit": step_limit or self.step_limit or DEFAULT_STEP_LIMIT,
            "arm": arm,
        }
        if self.signal_cycle_s is not None:
            options["signal_cycle_s"] = self.signal_cycle_s
        return options


@dataclass(frozen=True, kw_only=True)
class PlannedMove:
    """A move the plan has: its name for the report, joint or linear, where the TCP ends (None: the kind judges
    the pose itself, e.g. a part on a moving belt), how it moves (TCP speed mm/s, blending zone mm, an exact
    stop, a joint move's axis speed percent), where the controller's rule puts the arm (deg; None: within the
    joint limits is enough), the payload in force (TOOL_LOAD, or mass kg and centre of gravity mm) and the tool
    in force."""

    name: str
    kind: str
    tcp2base: np.ndarray | None = field(default=None, compare=False)
    exact: bool = False
    speed_mm_s: float | None = None
    zone_mm: float = 0.0
    joint_percent: float | None = None
    joints: np.ndarray | None = field(default=None, compare=False)
    payload: Any = TOOL_LOAD
    tolerance: tuple[float, float] | None = None  # (mm, deg) where the plan's pose is known less exactly
    tool: Any = "cell"  # the tool in force: "cell" ([cell.tool]), a tcp2flange (4x4 mm), None: not planned
    tool_tolerance: float | None = None  # mm, where the planned tool is known less exactly (a TCP measured)


@dataclass(frozen=True)
class PlannedOutput:
    """A digital output the plan sets: name as the program has it, value, after how many moves, and why."""

    name: str
    value: bool
    after_moves: int
    what: str = ""


@dataclass(frozen=True)
class Stored:
    """What a program leaves for later programs (tool data, counters), read where it is stored."""

    name: str
    value: Any
    tolerance: float = 0.0
    what: str = ""
    if_unset: Any = None  # what a name the run never wrote holds (an output register keeps the PLC's value)


@dataclass(frozen=True)
class Expectation:
    """What a correct program does in a case: stop with this message (None: it ends without a stop), these moves
    in this order, these outputs (None: the plan says nothing of them), this data stored at the end, these
    numbers in its log lines (name, value, tolerance)."""

    halt: str | None
    moves: tuple[PlannedMove, ...] = ()
    outputs: tuple[PlannedOutput, ...] | None = ()
    stored: tuple[Stored, ...] = ()
    logged: tuple[tuple[str, float, float], ...] | None = None
    joints_checked: bool = True  # the moves' joints are compared with the plan's (False: limits only)
    # the moves' joints, computed only when the poses matched (the controller's rule solves them), or None
    planned_joints: Callable[[], list | None] | None = field(default=None, compare=False)
    output_names: frozenset[str] | None = None  # the outputs the plan speaks for (None: every output of the run)


@dataclass
class Judgement:
    """A kind's verdict on a run before the common checks: the expectations a correct program may meet (the
    first that passes counts), whether the case sits on a boundary, a problem the kind found itself (None:
    none), the kind's figures of this run (counted when it passes) and what the physical situation demands
    beyond the cell's own model (a cell that contradicts its devices fails on every target)."""

    accepted: list[Expectation]
    boundary: bool = False
    problem: str | None = None
    figures: object = None
    truth: str | None = None  # where the run met the plan but the physical situation demands otherwise
    errors: tuple[list, list] = ((), ())  # position (mm) and rotation (deg) errors the kind measured itself


def refuses_start(cell, target, case, allowed: tuple[str, ...] = ("home",)) -> str | None:
    """The restart rule (targets/<t>.toml restart = "at_home"): a program started anywhere but where its kind
    lets it start (`allowed`: home, and a station's retreat for the station program) stops before it moves,
    with this message (as the target prints it); None where the target's programs may start anywhere, or the
    cell has no arm to be away with."""
    if case.start in allowed or target.program.get("restart") != "at_home":
        return None
    if cell.robot is None or target.name not in cell.robot.arms:
        return None
    return Emitter(target).string(halt_message(cell, NOT_AT_HOME, None, 0))
