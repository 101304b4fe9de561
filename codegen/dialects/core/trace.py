"""What a run records: the moves, the outputs set, the messages and how the run ended."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass
class MoveEvent:
    kind: str  # "joint" or "linear"
    tcp2base: np.ndarray | None  # 4x4 float64, mm (a joint target's: filled when the run's moves are solved)
    line: int
    settings: dict = field(default_factory=dict)  # how the arm moves there, in the dialect's terms
    joints: np.ndarray | None = None  # deg, where the arm's axes end (None: the run has no arm)
    solutions: np.ndarray | None = None  # (8, 6) deg: every analytic solution of the pose (a pose target)
    end_time: float = 0.0  # when the arm arrives, in the program's clock (s)
    start_time: float = 0.0  # when the arm sets off (the previous move's end, or the instruction's moment) (s)
    file: str = ""  # the file of `line` where a program is several files of code (a RAPID task's modules)
    arc: object = None  # a circular move's TCP path from where it set off (watch.Path: pose(s)), where the run knows it


@dataclass
class SignalEvent:
    """A digital output the program set: its name in the program's terms, the value, where, when (s),
    whether the arm was still moving then and how many moves the program had commanded before it."""

    name: str
    value: bool
    line: int
    time: float
    moving: bool
    after_moves: int
    tcp2base: np.ndarray | None = None  # where the tool is at that moment (base frame), where known


@dataclass
class Trace:
    messages: list[str] = field(default_factory=list)
    message_times: list[float] = field(default_factory=list)  # when each message was written (s)
    moves: list[MoveEvent] = field(default_factory=list)
    outputs: list[SignalEvent] = field(default_factory=list)
    halted: bool = False
    halt_message: str | None = None
    steps: int = 0
    kept: dict = field(default_factory=dict)  # Program.run(keep=...): those names' values when the run ended
    ended: str | None = None  # why the run ended before the program did (a limit: max_moves, max_seconds, steps)
    clock: float = 0.0  # the program's clock when the run ended (s)
    # signals the program used that no device or declaration provides: simulated I/O (inputs read as off, outputs
    # recorded), named so that a report shows them (Machine.simulated)
    simulated: list[str] = field(default_factory=list)
    # what the run took as a fresh controller has it where the program's files do not give it (Machine.warn)
    warnings: list[str] = field(default_factory=list)


NO_MESSAGE = "the program stopped without a message"  # a stop whose program wrote no message before it


def halt_text(trace: Trace) -> str:
    """How a report names the program's stop: its message, or that there was none (never "None")."""
    return trace.halt_message if trace.halt_message is not None else NO_MESSAGE
