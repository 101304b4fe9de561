"""One test base for every dialect's interpreter: the checks all four pass, each dialect supplying its snippets."""

from __future__ import annotations

import re

import pytest

from codegen.dialects.core.machine import Machine, Trace
from codegen.dialects.core.program import Program
from codegen.dialects.core.values import RunError, StepLimitError


class SetsOnWait:
    """A device that, whenever the program waits, sets one variable to 1 (once) and counts the waits."""

    def __init__(self, name: str) -> None:
        self.name = name
        self.waits = 0
        self.undeclared_write: bool | None = None

    def on_wait(self, machine: Machine, where: str) -> bool:
        self.waits += 1
        self.undeclared_write = machine.write_variable("NO_SUCH_VARIABLE_9", 1)
        if machine.read_variable(self.name) == 1:
            return False
        assert machine.write_variable(self.name, 1)
        return True


class DialectTests:
    """Subclasses (one per dialect) set filename and the snippets below, and define load()."""

    filename: str
    # Whole programs. Messages are the texts the program writes (textmsg, TPWrite, SET_KRLMSG).
    COPIES: str  # b := a, then a component of b changed: writes a's component (1), then b's (5)
    BY_VALUE: str  # a routine changes its by-value parameter: the caller then writes its own (1)
    BY_REFERENCE: str | None  # a routine changes its by-reference parameter: the caller writes 99
    RUNAWAY: str  # a loop that never ends
    HALT: str  # writes "stop here", halts, then would write "never" or move
    SYNTAX_ERROR: tuple[str, int]  # a program and the line of its syntax error
    UNDEFINED: tuple[str, int]  # a program reading the undefined variable y (or Q) on that line
    OUT_OF_RANGE: tuple[str, str]  # a program reading past an array's end, and the message expected
    FLOAT32: str  # writes 16777217.0, which float32 holds as 16777216
    WAIT: str  # waits until the variable WAIT_NAME is 1, then writes "go"
    WAIT_NAME: str

    def load(self, text: str) -> Program:
        raise NotImplementedError

    def run(self, text: str, **kwargs) -> Trace:
        return self.load(text).run({}, **kwargs)

    def test_assignment_copies_values(self):
        program = self.load(self.COPIES)
        assert program.run({}).messages == ["1", "5"]
        assert program.run({}).messages == ["1", "5"]  # a run never changes the next run's start

    def test_by_value_parameters_do_not_leak(self):
        assert self.run(self.BY_VALUE).messages == ["1"]

    def test_by_reference_parameters_write_back(self):
        if self.BY_REFERENCE is None:
            pytest.skip(f"{self.filename}: the language has no by-reference parameters")
        program = self.load(self.BY_REFERENCE)
        assert program.run({}).messages == ["99"]
        assert program.run({}).messages == ["99"]

    def test_step_limit_stops_a_runaway_loop(self):
        pattern = rf"^{re.escape(self.filename)}:\d+:\d+: step limit 100 reached \(runaway loop\?\)$"
        with pytest.raises(StepLimitError, match=pattern):
            self.run(self.RUNAWAY, step_limit=100)

    halt_resumes = False  # the halt statement pauses: the operator's start runs the rest (KRL HALT)

    def test_halt_keeps_the_last_message(self):
        """HALT is followed by a move: it runs only where the controller resumes after a halt."""
        trace = self.run(self.HALT)
        assert trace.halted and trace.halt_message == "stop here"
        assert trace.messages == ["stop here"] and len(trace.moves) == (1 if self.halt_resumes else 0)

    def test_syntax_error_lists_what_a_user_can_write(self):
        """Keywords and symbols quoted as written, or "a name", "a number" ...: no grammar rule names."""
        with pytest.raises(RunError) as info:
            self.load(self.SYNTAX_ERROR[0])
        listed = str(info.value).split("expected one of ", 1)[1]
        quoted = r"'(?:[^'\\]|\\.)*'|\"(?:[^\"\\]|\\.)*\""
        items = quoted + "|a name|a number|an integer|a string|the end of the line|a comment"
        leftover = re.sub(rf"(?:{items})(?:, |$)", "", listed)
        assert leftover == "", f"not in a user's words: {leftover!r} in {listed!r}"

    def test_syntax_error_names_file_line_and_column(self):
        text, line = self.SYNTAX_ERROR
        with pytest.raises(RunError, match=rf"^{re.escape(self.filename)}:{line}:\d+: syntax error.*, expected one of"):
            self.load(text)

    def test_run_error_names_file_line_and_column(self):
        text, line = self.UNDEFINED
        with pytest.raises(RunError, match=rf"^{re.escape(self.filename)}:{line}:\d+: undefined variable [yQ](: .+)?$"):
            self.run(text)

    def test_index_out_of_range(self):
        text, message = self.OUT_OF_RANGE
        with pytest.raises(RunError, match=rf"^{re.escape(self.filename)}:\d+:\d+: {message}$"):
            self.run(text)

    def test_numbers_are_float32(self):
        assert self.run(self.FLOAT32).messages == ["16777216"]

    def test_a_device_acts_when_the_program_waits(self):
        device = SetsOnWait(self.WAIT_NAME)
        trace = self.load(self.WAIT).run({}, devices=[device])
        assert trace.messages == ["go"]
        assert device.waits >= 1 and device.undeclared_write is False

    def test_a_wait_without_devices_fails(self):
        with pytest.raises(RunError, match=rf"^{re.escape(self.filename)}:\d+:\d+: "):
            self.run(self.WAIT, step_limit=1000)
