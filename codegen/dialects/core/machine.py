"""The machine a compiled program runs on: routines, frames, one run's state, clock and devices (traces: trace.py)."""

from __future__ import annotations

import math
from typing import Protocol

import numpy as np

from codegen.dialects.core.arm import ArmState
from codegen.dialects.core.ramp import travel_seconds
from codegen.dialects.core.runstate import RunState
from codegen.dialects.core.trace import MoveEvent, SignalEvent, Trace
from codegen.dialects.core.values import Halt, LimitReached, RunError, StepLimitError

__all__ = ["MoveEvent", "SignalEvent", "Trace"]  # re-exported: callers import them here (they live in trace.py)

DEFAULT_STEP_LIMIT = 200_000
# A number past float32's range is an error of the program, as on the controllers, not an inf and a warning line:
# numpy raises FloatingPointError in the program's operators, which their guards name.
OVERFLOW = "raise"


def halt(fr, *_ignored) -> None:
    """End the program; its last message is the operator's message."""
    messages = fr.m.trace.messages
    raise Halt(messages[-1] if messages else None)


def pause(fr, *_ignored) -> None:
    """Stop where the controller resumes at the next statement when the operator presses start (a
    dialect's halt_resumes, or a builtin that pauses): the stop is recorded with its message and the
    run goes on as after that restart, so whatever the program does next (a move with a rejected
    reading) is in the trace."""
    trace = fr.m.trace
    if not trace.halted:
        trace.halted = True
        trace.halt_message = trace.messages[-1] if trace.messages else None


def step_limit_error(where: str, machine: Machine) -> StepLimitError:
    return StepLimitError(f"{where}: step limit {machine.step_limit} reached (runaway loop?)")


class Device(Protocol):
    """Simulated equipment beside the controller (the vision PC): called whenever the program waits,
    it reads and writes the program's variables through Machine.read_variable and
    Machine.write_variable, at the time Machine.clock; it may look at Machine.moving."""

    def on_wait(self, machine: Machine, where: str) -> bool:
        """Act on the program's state; True when something changed (where: file:line:column)."""
        ...

    def next_time(self, machine: Machine) -> float | None:
        """When the device will next act on its own (an answer due), or None: nothing planned
        (optional: a device without it acts only when the program waits)."""
        ...


class ProgramCode(Protocol):
    """What a run needs of the compiler that built the program (codegen/dialects/core/compiler.py Compiler:
    named here by its methods, so that the machine does not import the compiler that imports it)."""

    routines: dict

    def new_state(self) -> RunState: ...

    def norm(self, name: str) -> str: ...

    def inject_inputs(self, machine: Machine) -> None: ...

    def accepts_input(self, name: str, globals_: dict) -> bool: ...

    def kept(self, machine: Machine, name: str): ...

    def call_routine(self, fr: Frame, name: str, args: list, kwargs: dict, where: str, arg_setters=None): ...

    def device_read(self, machine: Machine, name: str): ...

    def device_write(self, machine: Machine, name: str, value) -> bool: ...


class CompiledProgram(Protocol):
    """What a run needs of its program (codegen/dialects/core/program.py Program: named here by its attributes, so
    that the machine does not import the program that imports it)."""

    name: str
    compiler: ProgramCode


class Routine:
    """A user procedure or function: parameters, compiled body, declared return type."""

    __slots__ = ("body", "decls", "defaults", "entry", "line", "name", "params", "return_type")

    def __init__(self, name, params, body, return_type=None, line=0, decls=None, defaults=None) -> None:
        self.name = name
        self.params = params  # list of (name, mode, type or None)
        self.body = body
        self.return_type = return_type
        self.line = line
        self.decls = decls or []  # (name, type, init closure) local declarations
        self.defaults = defaults or {}  # parameter name -> its default value's closure (fr -> value)
        self.entry = None  # the compiled call (Compiler.entry)


class Frame:
    __slots__ = ("m", "types", "vars")

    def __init__(self, machine: Machine, vars_=None, types=None) -> None:
        self.m = machine
        self.vars = vars_ if vars_ is not None else {}
        self.types = types if types is not None else {}


class Machine:
    """State of one run: globals, injected inputs, trace, step counter."""

    def __init__(
        self,
        program: CompiledProgram | None,
        inputs: dict,
        step_limit: int,
        devices: tuple[Device, ...] = (),
        arm=None,
        signal_cycle_s: float | None = None,
    ) -> None:
        self.program = program
        self.arm = ArmState(arm)  # the arm's tool and joints (no checks when arm is None)
        self.globals: dict = {}
        self.global_types: dict = {}
        self.inputs = inputs
        self.outputs: dict = {}
        self.devices = devices
        # each device's optional parts looked up once for the run (a run's devices do not change)
        self._on_wait = tuple(d.on_wait for d in devices)
        self._next_times = tuple(d.next_time for d in devices if hasattr(d, "next_time"))
        self._live = tuple(d.live for d in devices if getattr(d, "live", None) is not None)
        self.trace = Trace()
        self.step_limit = step_limit
        self.steps = 0
        self.move_limit: int | None = None  # Program.run(max_moves=...): the run ends after that many moves
        self.time_limit = math.inf  # Program.run(max_seconds=...): the run ends once the clock passes it
        # the dialect's state: its system variables, handles, ... (no program: a device tried alone)
        self.state = RunState() if program is None else program.compiler.new_state()
        self.device_state: dict = {}  # a device's own state in this run, by the device (a counter of answers)
        # Time (s since the program started): the program's clock, and when the arm finishes the moves
        # commanded so far (later than the clock while a controller's program runs ahead of its motion)
        self.clock = 0.0
        self.arm_until = 0.0
        self.last_move: MoveEvent | None = None
        self.signals: dict[str, bool] = {}  # digital inputs and outputs by name (devices set the inputs)
        # how much later than it asks each sleep of the program ends (a device that models the controller's loop
        # passes: codegen/sim/belt.py BeltLine; 0: exactly)
        self.sleep_overhead_s = max((float(getattr(d, "sleep_overhead_s", 0.0)) for d in devices), default=0.0)
        # a controller's belt tracking: an object whose offset_mm(t) (3 mm, base frame) lies over every
        # commanded pose while it is on (a dialect's tracking built-ins), None: off
        self.tracking = None
        self._last_tcp2base: np.ndarray | None = None
        # inputs that switch with the tool's pose while it moves (codegen/dialects/core/watch.py): the moves'
        # paths in time and the watched inputs, when a device switches so and the controller's cycle is known
        self.watching = None
        if signal_cycle_s is not None and any(hasattr(d, "switches") for d in devices):
            from codegen.dialects.core.watch import Watching

            self.watching = Watching(self, signal_cycle_s)

    # --- time --------------------------------------------------------------------------------
    @property
    def moving(self) -> bool:
        """The arm is still executing a commanded move while the program runs on."""
        return self.arm_until > self.clock

    def move(
        self,
        event: MoveEvent,
        speed_mm_s: float | None = None,
        runs_ahead: bool = False,
        seconds: float | None = None,
        via: np.ndarray | None = None,
        path=None,
        accel_mm_s2: float | None = None,
    ) -> None:
        """Record a commanded move. It starts when the previous one ends and takes travel_seconds;
        the program waits for it (the clock reaches its end) unless the controller runs ahead of its
        motion (an advance run, a fly-by point): then the clock stays and the arm is moving
        until an instruction that waits for it (Machine.arrive). seconds: the move's duration where the
        caller knows it (a move relative to a tracked belt); via: a circular move's circle point (its
        duration is the arc's length over the speed); path: the move's own path where the dialect knows it
        better (codegen/dialects/core/watch.py Path: a circle whose orientation turns); accel_mm_s2: a straight
        move's path acceleration where the dialect models it (travel_seconds)."""
        self.trace.moves.append(event)
        if via is not None and self._last_tcp2base is not None and event.tcp2base is not None:
            from codegen.dialects.core.watch import Path

            event.arc = path if path is not None else Path(self._last_tcp2base, event.tcp2base, via)
        start = max(self.clock, self.arm_until)
        if seconds is None and path is not None and speed_mm_s:
            seconds = path.length / speed_mm_s
        if seconds is None:
            if via is not None and self._last_tcp2base is not None and event.tcp2base is not None and speed_mm_s:
                from codegen.dialects.core.watch import Path

                seconds = Path(self._last_tcp2base, event.tcp2base, via).length / speed_mm_s
            else:
                seconds = travel_seconds(self._last_tcp2base, event.tcp2base, speed_mm_s, accel_mm_s2)
        self.arm_until = start + seconds
        event.start_time, event.end_time = start, self.arm_until
        if self.watching is not None:
            self.watching.record(start, self.arm_until, self._last_tcp2base, event, via, self.arm.tcp2flange, path)
        self._last_tcp2base = event.tcp2base
        self.last_move = event
        if not runs_ahead:
            self.clock = self.arm_until
            self.deliver()
        if self.move_limit is not None and len(self.trace.moves) >= self.move_limit:
            raise LimitReached(f"{self.move_limit} moves made (the run's limit of moves)")
        if self.arm_until > self.time_limit:  # the motion commanded so far (a program may run ahead of it)
            self.past_time_limit()

    def past_time_limit(self) -> None:
        """The clock passed the run's time limit: the run ends here (LimitReached)."""
        raise LimitReached(f"the program's clock passed {self.time_limit:g} s (the run's time limit)")

    def cut_move(self, event: MoveEvent, t: float, pose: np.ndarray) -> None:
        """The last commanded move ends early: at time t, at this pose (a search that stops at its hit; no
        stopping distance is modelled)."""
        if self.last_move is not event:
            raise RunError("a move can only be cut short while it is the last one commanded")
        if self.watching is not None:
            self.watching.cut(event, t, pose)
        event.tcp2base = pose
        event.end_time = t
        self.arm_until = t
        self._last_tcp2base = pose

    def deliver(self) -> None:
        """The watched inputs' edges up to the clock reach their handlers (interrupts, traps, threads)."""
        if self.watching is not None:
            self.watching.deliver()

    def pose_now(self) -> np.ndarray | None:
        """Where the tool is at the clock: on the path of a move under way where the clock knows it."""
        if self.watching is not None:
            pose = self.watching.pose_at(self.clock)[0]
            if pose is not None:
                return pose
        return self.tool_pose()

    def set_output(self, name: str, value: bool, where: str) -> None:
        """A digital output set by the program, recorded with the moment (the devices act on it)."""
        self.signals[name] = bool(value)
        line = int(where.split(":")[1]) if where.count(":") >= 2 else 0
        event = SignalEvent(name, bool(value), line, self.clock, self.moving, len(self.trace.moves), self.tool_pose())
        self.trace.outputs.append(event)

    def output_written(self, where: str) -> None:
        """The program wrote an output a device watches (a register, a group): the devices see it now,
        not only at the program's next wait."""
        self.wait(where)

    def input_signal(self, name: str, default=False):
        """An input as the program reads it now: a device's live value (an encoder's count that changes
        with time, device.live(name, t)), else what the devices last set, else default."""
        if self.watching is not None and self.watching.handles(name):
            return self.watching.value(name, self.clock)
        for live in self._live:
            value = live(name, self.clock)
            if value is not None:
                return value
        return self.signals.get(name, default)

    def simulated(self, name: str) -> None:
        """A signal the program reads that nothing has set (no device, no declaration, no --signal): simulated
        I/O, named once in the trace (dropped at the end where a device set it after all)."""
        if name not in self.trace.simulated:
            self.trace.simulated.append(name)

    def warn(self, text: str) -> None:
        """Something the run assumed that the program's files do not say, named once in the trace."""
        if text not in self.trace.warnings:
            self.trace.warnings.append(text)

    def message(self, text: str) -> None:
        """A message the operator sees (the teach pendant's log or a dialog), with the moment."""
        self.trace.messages.append(text)
        self.trace.message_times.append(self.clock)

    def tool_pose(self) -> np.ndarray | None:
        """Where the tool is now (base frame): the last move's pose, moved by the tracked belt's
        travel since that move's end while tracking is on; before any move, where the arm stood at the start
        (its joints and model known), else None."""
        if self.tracking is not None:
            return self.tracking.pose_now(self)
        return self.arm.standing_pose() if self.last_move is None else self.last_move.tcp2base

    def arrive(self, where: str) -> None:
        """An instruction that waits until the arm stands still (an advance-run stop, an in-position
        wait): the devices see the moment first (a request made while the arm moves), then the clock
        reaches the end of the motion."""
        if self.moving:
            self.wait(where)
            self.clock = self.arm_until
            self.deliver()

    def elapse(self, seconds: float, where: str) -> None:
        """The program sleeps (WAIT SEC, sleep, WaitTime): the arm finishes its moves first (where
        the controller's sleep waits for it: callers decide), the devices act at every event in between; a sleep
        ends sleep_overhead_s later than it asks (where a device models the controller so)."""
        end = self.clock + max(0.0, seconds) + (self.sleep_overhead_s if seconds > 0 else 0.0)
        self.wait(where)
        while True:
            due = self.next_device_time()
            if due is None or due > end:
                break
            self.clock = max(self.clock, due)
            self.deliver()
            self.step(where)
            self.wait(where)
        self.clock = end
        self.deliver()
        self.wait(where)
        if self.clock > self.time_limit:
            self.past_time_limit()

    def next_device_time(self) -> float | None:
        first = None
        for next_time in self._next_times:
            t = next_time(self)
            if t is not None and (first is None or t < first):
                first = t
        return first

    def wait_for(self, cond, where: str, max_seconds: float | None = None, keyword: str = "wait") -> bool:
        """Wait until cond() (a condition only a device can make true): True when it came true, False
        at max_seconds (the clock then stands at the deadline); with no limit, a condition no device
        will make true is an error (the controller would wait forever)."""
        deadline = None if max_seconds is None else self.clock + max(0.0, max_seconds)
        while not cond():
            self.step(where)
            if self.wait(where):
                continue
            due = self.next_device_time()
            if due is not None and due <= self.clock:
                due = self.clock  # due now: act again
            if self.clock > self.time_limit:
                self.past_time_limit()
            if due is None or (deadline is not None and due > deadline):
                if deadline is None and self.time_limit < math.inf:  # the run's time limit ends the wait
                    self.clock = max(self.clock, self.time_limit)
                    raise LimitReached(
                        f"{where}: {keyword} a condition that nothing here makes true, until the run's time limit"
                    )
                if deadline is None:
                    raise RunError(f"{where}: {keyword} a condition that nothing here makes true (waits forever)")
                self.clock = deadline
                self.deliver()
                return bool(cond())
            self.clock = due
            self.deliver()
        return True

    def wait(self, where: str) -> bool:
        """The program waits (WAIT FOR, WaitUntil, sync()): every device may act on the program's
        variables; True when one of them did (the wait's condition is then tested again). The arm has
        finished its moves when a device looks at it."""
        if not self._on_wait:
            return False
        if self.arm.pending:
            self.arm.resolve()
        acted = False
        for on_wait in self._on_wait:
            if on_wait(self, where):
                acted = True
        return acted

    def read_variable(self, name: str):
        """A variable or register by its name in the program, for a device (None: not declared)."""
        return self.program.compiler.device_read(self, name)

    def write_variable(self, name: str, value) -> bool:
        """Store into a variable or register by its name in the program, coerced to its type, for a
        device; False when the program declares no such variable."""
        return self.program.compiler.device_write(self, name, value)

    def step(self, where: str) -> None:
        self.steps += 1
        if self.steps > self.step_limit:
            raise step_limit_error(where, self)
