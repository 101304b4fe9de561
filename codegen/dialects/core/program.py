"""A compiled program run many times: its set-up once, each run from a copy of it, a run's errors with its trace."""

from __future__ import annotations

import gc
from collections.abc import Iterable
from contextlib import contextmanager

import numpy as np

from codegen.dialects.core.machine import (
    DEFAULT_STEP_LIMIT,
    OVERFLOW,
    Device,
    Frame,
    Machine,
    ProgramCode,
    Routine,
)
from codegen.dialects.core.runstate import RunState
from codegen.dialects.core.shared import SHARE_FROM, SharedGlobals
from codegen.dialects.core.trace import Trace
from codegen.dialects.core.values import Halt, LimitReached, RunError, Signal, op_error


class Program:
    """A parsed and compiled program, run many times with different inputs.

    `init` (module data, constant definitions) runs once; its globals are kept as a snapshot and
    every run starts from a shallow copy of it (values are never changed in place).
    """

    def __init__(self, name: str, compiler: ProgramCode, init, main: str | None, body=None) -> None:
        self.name = name
        self.compiler = compiler
        self.routines: dict[str, Routine] = compiler.routines
        self.init = init  # callable: module data / constant top-level statements
        self.main = main  # routine to call after init, or None
        self.body = body  # callable run after init when there is no main routine
        self._snapshot: tuple[dict, dict, RunState] | None = None

    def _prepare(self, step_limit: int) -> tuple[dict, dict, RunState]:
        if self._snapshot is None:
            machine = Machine(self, {}, step_limit)
            try:
                with np.errstate(over=OVERFLOW):
                    self.init(Frame(machine, machine.globals, machine.global_types))
            except FloatingPointError as exc:  # past float32 outside an operator's guard (a built-in's result)
                raise op_error(self.name, exc) from None
            globals_, types = machine.globals, machine.global_types
            if len(globals_) >= SHARE_FROM:  # a large program: shared by its runs, not copied (core/shared.py)
                globals_, types = SharedGlobals(globals_), SharedGlobals(types)
            self._snapshot = (globals_, types, machine.state)
        return self._snapshot

    def prepare(self) -> None:
        """Run the program's set-up once now (module data, constant definitions: what every run starts from),
        so that a RunError there is the program's, reported once when it is loaded."""
        self._prepare(DEFAULT_STEP_LIMIT)

    def unknown_inputs(self, names) -> list[str]:
        """The input names this program has no variable or register for (a misspelt --input)."""
        globals_, _types, _state = self._prepare(DEFAULT_STEP_LIMIT)
        return [name for name in names if not self.compiler.accepts_input(name, globals_)]

    def run(
        self,
        inputs: dict | None = None,
        step_limit: int = DEFAULT_STEP_LIMIT,
        devices: Iterable[Device] = (),
        arm=None,
        signals: dict | None = None,
        start_joints=None,
        keep: tuple[str, ...] = (),
        signal_cycle_s: float | None = None,
        max_moves: int | None = None,
        max_seconds: float | None = None,
    ) -> Trace:
        """One run from the initial globals with these inputs; devices (simulated equipment beside
        the controller) act whenever the program waits; arm (codegen.robot.arms.Arm): the arm whose
        joints each move must reach by the controller's rules (None: poses only); signals: digital
        inputs by name at the start; start_joints: where the arm stands (deg; None: unknown); keep: names
        of globals or written outputs whose values the trace keeps from the end of the run; signal_cycle_s: how
        often the controller reads its inputs (a device that switches with the tool's pose needs it);
        max_moves, max_seconds: the run ends cleanly after that many moves, or once the program's clock passes
        that many seconds (an endless cell program), its trace kept and Trace.ended saying why. A step limit
        reached raises StepLimitError, whose `trace` holds what ran until then (as any RunError of the run)."""
        globals_, types, state = self._prepare(step_limit)
        machine = Machine(self, dict(inputs or {}), step_limit, tuple(devices), arm, signal_cycle_s)
        machine.move_limit = max_moves
        if max_seconds is not None:
            machine.time_limit = max_seconds
        machine.signals.update(signals or {})
        if start_joints is not None:  # where the arm stands when the program starts (deg)
            machine.arm.stand_at(start_joints)
        shared = isinstance(globals_, SharedGlobals)
        if shared:  # the stores are logged and undone at the end
            globals_.undo()
            types.undo()
            machine.globals, machine.global_types = globals_, types
        else:  # values are never changed in place: a shallow copy is the run's own
            machine.globals, machine.global_types = dict(globals_), dict(types)
        machine.state = state.copy()
        try:
            with np.errstate(over=OVERFLOW):
                return self._run(machine, keep)
        finally:
            if shared:
                globals_.undo()
                types.undo()

    def _run(self, machine: Machine, keep: tuple[str, ...]) -> Trace:
        frame = Frame(machine, machine.globals, machine.global_types)
        trace = machine.trace
        try:
            self.compiler.inject_inputs(machine)
            if self.main is not None:
                self.compiler.call_routine(frame, self.main, [], {}, "<main>")
            elif self.body is not None:
                signal = self.body(frame)
                if isinstance(signal, Signal) and signal.kind in ("break", "continue"):
                    raise RunError(f"{self.name}: {signal.kind} outside a loop")
        except RecursionError:
            message = f"{self.name}: routine calls nested too deeply (runaway recursion?)"
            raise self._kept(RunError(message), machine) from None
        except Halt as halt:
            trace.halted = True
            trace.halt_message = halt.args[0] if halt.args else None
        except LimitReached as limit:
            trace.ended = str(limit)
        except RunError as exc:  # what ran until then stays readable (codegen run prints it)
            raise self._kept(exc, machine) from None
        except FloatingPointError as exc:  # past float32 outside an operator's guard (a built-in's result)
            raise self._kept(op_error(self.name, exc), machine) from None
        try:
            machine.arm.resolve()  # the joints of every move, by the controller's rules (RunError if refused)
        except FloatingPointError as exc:  # a pose so far out that solving it overflows: the program's
            raise op_error(self.name, exc) from None
        if trace.simulated:  # an input a device set after all (a gripper's feedback) was not simulated
            trace.simulated = [name for name in trace.simulated if name not in machine.signals]
        trace.steps = machine.steps
        trace.clock = machine.clock
        for name in keep:
            machine.trace.kept[name] = self.compiler.kept(machine, name)
        return machine.trace

    @staticmethod
    def _kept(exc: RunError, machine: Machine) -> RunError:
        """The error with the run's trace until then (exc.trace); exc.solve_joints() solves its moves' joints
        where a caller wants them (not here: verify's runs that fail by design would pay for it)."""
        trace = machine.trace
        trace.steps, trace.clock, trace.ended = machine.steps, machine.clock, str(exc)
        exc.trace = trace
        exc.solve_joints = machine.arm.resolve
        return exc


@contextmanager
def frozen_heap():
    """Python's collector leaves what is alive now alone (gc.freeze) until the block ends: the loaded
    programs, cell and cases are scanned by no full collection while the cases run (a 1,000-station
    program made them a third of the time), and all of it is collectable again afterwards."""
    gc.freeze()
    try:
        yield
    finally:
        gc.unfreeze()
