"""The operator's confirmation before the production tool changes: the old and new X, Y, Z shown, a Yes/No dialog."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from codegen.emit import Emitter
from codegen.kinds.laser import program as lp
from codegen.kinds.laser.kind import KIND
from codegen.kinds.laser.section import production_tool
from codegen.sim.operator import Operator

# Where a target's facts say `confirm` ([program.laser]), the program shows the production tool's X, Y, Z as they
# are (TOOL_NOW) and the TCP found (TCP_FOUND), then asks (CONFIRM) with the softkeys YES and NO; YES writes the
# TCP (WRITTEN), anything else leaves the production tool as it was (NOT_WRITTEN). Verify's operator answers YES
# in every case but one, "confirmation_refused", where it answers NO.
YES, NO = "Yes", "No"  # the dialog's softkeys 1 and 2 (labels of at most 10 characters)
TOOL_NOW = "laser: {tool} now, flange frame mm: "
TCP_FOUND = "laser: TCP found, flange frame mm: "
CONFIRM = "laser: write the TCP found into {tool}?"
NOT_WRITTEN = "laser: TCP not written, {tool} unchanged (not confirmed)"
REFUSED = "confirmation_refused"  # the case where the operator answers NO
UNANSWERED = "confirmation_unanswered"  # the case where nobody answers: the program waits, the tool unchanged
# How long a run waits for an answer that never comes (s of the program's clock): the whole calibration (about 40 s
# on the bundled cell) and a minute at the question; the run ends there (the controller would wait on)
WAIT_S = 120.0
NO_ANSWER = "no operator answers"  # the interpreter's error where a blocking question gets no answer (URScript)
VALUES_MM = 1e-3  # a number the message shows against the value it stands for (float32 printed in full)


def asks(target) -> bool:
    """Whether the target's program asks the operator before it writes the production tool."""
    return bool(KIND.facts(target).get("confirm"))


def texts(cell, target) -> dict[str, str]:
    """The messages with the production tool as the operator knows it (a numbered tool: "tool 3")."""
    value = production_tool(cell, target.name)
    tool = f"tool {value}" if KIND.facts(target)["production_tool"]["form"] == "number" else str(value)
    return {
        "tool_now": TOOL_NOW.format(tool=tool),
        "tcp_found": TCP_FOUND,
        "confirm": CONFIRM.format(tool=tool),
        "not_written": NOT_WRITTEN.format(tool=tool),
    }


def context(cell, target, emitter: Emitter) -> dict:
    """The template's strings (emitter.string: inert in the program), and whether it asks."""
    if not asks(target):
        return {"confirm": None}
    out = {key: emitter.string(text) for key, text in texts(cell, target).items()}
    return {"confirm": {**out, "yes": emitter.string(YES), "no": emitter.string(NO)}}


def cases(target, quiet) -> list:
    """The operator refusing the change, and nobody answering, where the target asks (the tool as designed, no
    noise)."""
    if not asks(target):
        return []
    return [replace(quiet, category=REFUSED, answer=NO), replace(quiet, category=UNANSWERED, answer=None)]


def devices(target, case) -> tuple:
    """The operator who answers the dialog, where the target asks: the case's answer; none, an operator who looks
    away (the dialog stays shown)."""
    if not asks(target):
        return ()
    return (Operator([] if case.answer is None else [case.answer], then_silent=True),)


def unanswered(target, case) -> bool:
    return asks(target) and case.answer is None


def refused(target, case) -> bool:
    return asks(target) and case.answer != YES


def _numbers(messages: list[str], prefix: str) -> list[float] | None:
    for message in messages:
        if message.startswith(prefix):
            try:
                return [float(v) for v in message[len(prefix) :].replace(",", " ").split()]
            except ValueError:
                return None
    return None


def problem(cell, target, case, trace, previous: np.ndarray, tcp: list[float]) -> str | None:
    """Where the target asks and the program wrote or refused a TCP: the production tool's X, Y, Z as they were and
    the TCP found shown before the question, the question asked, and after it the TCP written (YES) or the message
    that the production tool is unchanged (NO)."""
    if not asks(target):
        return None
    said = {key: Emitter(target).string(text) for key, text in texts(cell, target).items()}
    messages = list(trace.messages)
    for key, want in (("tool_now", previous), ("tcp_found", tcp)):
        shown = _numbers(messages, said[key])
        if shown is None or len(shown) != 3:
            return f"no message {said[key]!r} with three numbers before the question"
        if max(abs(a - b) for a, b in zip(shown, want, strict=True)) > VALUES_MM:
            return f"{said[key]!r} shows {shown}, expected {[round(float(v), 4) for v in want]}"
    if said["confirm"] not in messages:
        return f"the operator was not asked ({said['confirm']!r})"
    after = messages[messages.index(said["confirm"]) + 1 :]
    written = any(m.startswith(Emitter(target).string(lp.WRITTEN)) for m in after)
    if refused(target, case):
        if said["not_written"] not in after or written:
            return f"the operator answered {case.answer}: expected {said['not_written']!r} and no TCP written"
    elif not written or said["not_written"] in after:
        return f"the operator answered {YES}: expected the TCP written"
    return None


def silence_problem(cell, target, trace) -> str | None:
    """Nobody answers: the run ends waiting at the question (the time limit, or the controller's wait that nothing
    answers), the question asked, no TCP written, no move after the question (the arm stands while it waits)."""
    said = Emitter(target).string(texts(cell, target)["confirm"])
    if trace.halted or trace.ended is None:
        return "nobody answers the question: expected the program to wait at it, it " + (
            f"stopped with {trace.halt_message!r}" if trace.halted else "ran to its end"
        )
    if said not in trace.messages:
        return f"nobody answers: the question {said!r} was not asked"
    asked = trace.message_times[trace.messages.index(said)]
    if any(m.startswith(Emitter(target).string(lp.WRITTEN)) for m in trace.messages):
        return "nobody answers: the TCP was written all the same"
    later = [m for m in trace.moves if m.start_time > asked + 1e-9]
    if later:
        return f"nobody answers: the arm moved on after the question (line {later[0].line}) instead of waiting"
    return None
