"""The FlexPendant: TPWrite, TPErase, TPReadFK and TPReadNum, answered by the run's simulated operator."""

from __future__ import annotations

import math
from collections.abc import Callable

from codegen.dialects.core.values import RunError, f32
from codegen.dialects.rapid import errors
from codegen.dialects.rapid.arguments import split_args
from codegen.dialects.rapid.functions import num_text, value_text
from codegen.dialects.rapid.signals import signal_ref
from codegen.dialects.rapid.types import STRING_MAX, num, rec

# Sources: ABB, "Technical reference manual - RAPID Instructions, Functions and Data types" (RobotWare 6/7),
# TPWrite, TPErase, TPReadFK, TPReadNum, as recalled (the manual's own text was not found during this work):
# - TPWrite String [\Num] | [\Bool] | [\Pos] | [\Orient] | [\Dnum]: the string and the value's text on the
#   FlexPendant's display, at most 80 characters; TPErase clears the display (the trace keeps what was written);
# - TPReadFK TPAnswer, TPText, TPFK1 ... TPFK5 [\MaxTime] [\DIBreak] [\DOBreak] [\BreakFlag]: the text is shown
#   with up to five function keys (stEmpty, the predefined "" (functions.py), or "": no key there); the program
#   waits until the operator presses one: TPAnswer (num) gets its number 1..5; \MaxTime (s) without an answer:
#   ERR_TP_MAXTIME, or with \BreakFlag the flag gets the error number and the program goes on;
# - TPReadNum TPAnswer, TPText [\MaxTime] [\DIBreak] [\DOBreak] [\BreakFlag]: the same with a number the
#   operator types. \DIBreak:=signal: the digital input that ends the dialog without an answer when it goes to 1
#   (or is 1 already) before a key is pressed: ERR_TP_DIBREAK, or with \BreakFlag the flag gets it and the program
#   goes on (as recalled; public programs pass a PLC's reset input, \DIBreak:=DI_...ResetAllRob \BreakFlag:=errvar,
#   and test errvar = ERR_TP_DIBREAK). Modelled so: the input read first, before the operator's answer; while
#   nobody answers, the dialog ends at the input's change or at \MaxTime. \DOBreak is not modelled (refused when
#   the program is loaded, naming the line).
# Confirmed by ABB's PC SDK reference (developercenter.robotstudio.com/api/pcsdk, the remote operator dialog that
# answers these instructions): UIInstructionType.TPReadFK "is used to display a question to the operator, who
# responds by selecting one out of 2-5 displayed function keys"; UITPReadFKEventArgs: TPText "the information text
# to be written on the display", TPFK1..TPFK5 "the text to be written on function key 1..5"; UITPFunctionKey: "if
# the function key 1 is pressed then 1 is returned, and so on". Public programs pass "" for a key they leave empty
# (as stEmpty) and test the \BreakFlag variable against ERR_TP_MAXTIME. Not confirmed here: the limits of the
# keys' texts; whether \BreakFlag is set to 0 when the operator answers (modelled so).
# The operator is the run's simulated operator (codegen/sim/operator.py: a device with press(machine, labels),
# `codegen run --answer`): TPReadFK's answer is a key's number or its label (compared without case), TPReadNum's a
# number. Without one, or once its answers are used, a read without \MaxTime stops the run with a message naming
# the line; with \MaxTime, that time passes without an answer.
KEYS = 5  # TPReadFK's function keys, TPFK1 ... TPFK5


def _operator(m):
    """The run's operator: the device that presses a dialog's keys (None: nobody answers)."""
    return next((d for d in m.devices if hasattr(d, "press")), None)


def press(m, labels: list[str | None]):
    """The run's operator's answer to a dialog with these keys (None: no answer)."""
    operator = _operator(m)
    return None if operator is None else operator.press(m, labels)


def _number(answer, where: str, name: str) -> float:
    """TPReadNum: the number the operator typed."""
    if isinstance(answer, str):
        try:
            answer = float(answer.strip())
        except ValueError:
            raise RunError(f"{where}: {name}: the operator's answer {answer!r} is not a number") from None
    if isinstance(answer, bool) or not isinstance(answer, int | float) or not math.isfinite(answer):
        raise RunError(f"{where}: {name}: the operator's answer {answer!r} is not a number")
    return float(answer)


def _key(answer, labels: list[str | None], where: str, name: str) -> float:
    """TPReadFK: the number of the key the operator pressed, one shown (a label, not stEmpty)."""
    shown = [i for i, label in enumerate(labels, 1) if label is not None]
    if isinstance(answer, bool) or not isinstance(answer, int | float) or answer not in shown:
        keys = ", ".join(f"{i} {labels[i - 1]}" for i in shown)
        raise RunError(f"{where}: {name}: the operator's answer {answer!r} is not one of the keys shown ({keys})")
    return float(answer)


def _show(m, value, where: str, what: str) -> str:
    if not isinstance(value, str):
        raise RunError(f"{where}: {what} needs a string")
    if len(value) > STRING_MAX:
        raise RunError(f"{where}: {what} text longer than {STRING_MAX} characters")
    m.message(value)
    return value


def tp_write(fr, args, kwargs, where) -> None:
    if len(args) != 1:
        raise RunError(f"{where}: TPWrite takes one string")
    text = args[0]
    if not isinstance(text, str):
        raise RunError(f"{where}: TPWrite needs a string")
    extra = set(kwargs) - {"NUM", "BOOL", "POS", "ORIENT", "DNUM"}
    if extra or len(kwargs) > 1:
        raise RunError(f"{where}: TPWrite takes one of \\Num, \\Bool, \\Pos, \\Orient, \\Dnum")
    if "NUM" in kwargs or "DNUM" in kwargs:
        text += num_text(num(kwargs.get("NUM", kwargs.get("DNUM")), where))
    elif "BOOL" in kwargs:
        text += value_text(bool(kwargs["BOOL"]))
    elif "POS" in kwargs:
        text += value_text(rec(kwargs["POS"], "POS", where))
    elif "ORIENT" in kwargs:
        text += value_text(rec(kwargs["ORIENT"], "ORIENT", where))
    _show(fr.m, text, where, "TPWrite")


def tp_erase(fr, args, kwargs, where) -> None:
    if args or kwargs:
        raise RunError(f"{where}: TPErase takes no arguments")


def _read(compiler, node, args_node, keys: int) -> Callable:
    """TPReadFK (keys 5) or TPReadNum (keys 0)."""
    name = "TPReadFK" if keys else "TPReadNum"
    refusal = name + " \\{arg} is not modelled here (\\MaxTime, \\DIBreak, \\BreakFlag)"
    positional, named = split_args(compiler, node, args_node, {"MAXTIME", "DIBREAK", "BREAKFLAG"}, refusal)
    if len(positional) != 2 + keys:
        what = "an answer variable, a text and five function keys" if keys else "an answer variable and a text"
        compiler.fail(node, f"{name} takes {what} ({len(positional)} arguments given)")
    for key in ("MAXTIME", "DIBREAK", "BREAKFLAG"):
        if key in named and named[key] is None:
            compiler.fail(node, f"{name} \\{key.title()} needs a value")
    store, where = compiler.lvalue(positional[0]), compiler.where(node)
    prompt, labels = compiler.expr(positional[1]), [compiler.expr(p) for p in positional[2:]]
    max_time = compiler.expr(named["MAXTIME"]) if "MAXTIME" in named else None
    flag = compiler.lvalue(named["BREAKFLAG"]) if "BREAKFLAG" in named else None
    breaker = signal_ref(compiler, node, named["DIBREAK"]) if "DIBREAK" in named else None

    def stop(fr, error_name: str, what: str) -> None:
        """The dialog ends without an answer: the error, or with \\BreakFlag its number in the flag."""
        error = errors.RapidError(errors.ERROR_NUMBERS[error_name], f"{where}: {name} {what}")
        if flag is None:
            raise error
        flag(fr, f32(error.errno))

    def run(fr):
        m = fr.m
        text = _show(m, prompt(fr), where, name)
        texts = [label(fr) for label in labels]
        if any(not isinstance(t, str) for t in texts):
            raise RunError(f"{where}: {name}: each function key's text is a string (stEmpty: no key)")
        shown = [t or None for t in texts]  # stEmpty (""): no key there
        if keys and not any(shown):
            raise RunError(f"{where}: {name}: no function key has a text: nothing could answer it")
        signal = None if breaker is None else breaker(fr)
        if signal is not None and m.input_signal(signal):
            stop(fr, "ERR_TP_DIBREAK", f"\\DIBreak: {signal} is 1")
            return
        answer = press(m, shown)
        if answer is None:
            if max_time is None and signal is None:
                raise RunError(
                    f"{where}: {name}: the program waits for the operator's answer to {text!r} and no operator "
                    f"answers in this run (codegen run --answer): or give {name} \\MaxTime to go on without one"
                )
            seconds = None if max_time is None else num(max_time(fr), where)
            if signal is not None and m.wait_for(lambda: bool(m.input_signal(signal)), where, seconds, name):
                stop(fr, "ERR_TP_DIBREAK", f"\\DIBreak: {signal} went to 1")
                return
            if signal is None:
                m.elapse(seconds, where)
            stop(fr, "ERR_TP_MAXTIME", "\\MaxTime passed")
            return
        value = _key(answer, shown, where, name) if keys else _number(answer, where, name)
        if flag is not None:
            flag(fr, f32(0))
        store(fr, f32(value))

    return run


SPECIAL = {
    "TPREADFK": lambda compiler, node, args_node: _read(compiler, node, args_node, KEYS),
    "TPREADNUM": lambda compiler, node, args_node: _read(compiler, node, args_node, 0),
}
BUILTINS = {"TPWRITE": tp_write, "TPERASE": tp_erase}
