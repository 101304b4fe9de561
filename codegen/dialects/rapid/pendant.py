"""The FlexPendant: TPWrite, TPErase, TPReadFK and TPReadNum, and the simulated operator who answers them."""

from __future__ import annotations

import math
from collections.abc import Callable

from codegen.dialects.core.values import RunError, f32
from codegen.dialects.rapid import errors
from codegen.dialects.rapid.arguments import split_args
from codegen.dialects.rapid.functions import num_text, value_text
from codegen.dialects.rapid.types import STRING_MAX, num, rec

# Sources: ABB, "Technical reference manual - RAPID Instructions, Functions and Data types" (RobotWare 6/7),
# TPWrite, TPErase, TPReadFK, TPReadNum, as recalled (the manual's text was not readable during this work):
# - TPWrite String [\Num] | [\Bool] | [\Pos] | [\Orient] | [\Dnum]: the string and the value's text on the
#   FlexPendant's display, at most 80 characters; TPErase clears the display (the trace keeps what was written);
# - TPReadFK TPAnswer, TPText, TPFK1 ... TPFK5 [\MaxTime] [\DIBreak] [\DOBreak] [\BreakFlag]: the text is shown
#   with up to five function keys (stEmpty: no key); the program waits until the operator presses one: TPAnswer
#   (num) gets its number 1..5; \MaxTime (s) without an answer: ERR_TP_MAXTIME, or with \BreakFlag the flag
#   gets the error number and the program goes on;
# - TPReadNum TPAnswer, TPText [\MaxTime] [\DIBreak] [\DOBreak] [\BreakFlag]: the same with a number the
#   operator types. \DIBreak and \DOBreak are not modelled (refused).
# The operator here is Operator (a device given to Program.run; `codegen run` gives none): answers in order.
# Without one, or once its answers are used, a read without \MaxTime stops the run with a message naming that.
ANSWERS_KEY = "<operator answers used>"  # Machine.extra: how many answers this run took


class Operator:
    """The person at the FlexPendant: answers the program's questions (TPReadFK: a key 1..5, TPReadNum: a
    number) in the order given. A device of the run (Program.run(devices=[...])): it acts on nothing else."""

    def __init__(self, answers) -> None:
        self.answers = [float(a) for a in answers]

    def on_wait(self, machine, where: str) -> bool:
        return False

    def next_time(self, machine) -> None:
        return None

    def answer(self, machine) -> float | None:
        used = machine.extra.get(ANSWERS_KEY, 0)
        if used >= len(self.answers):
            return None
        machine.extra[ANSWERS_KEY] = used + 1
        return self.answers[used]


def _operator_answer(m) -> float | None:
    for device in m.devices:
        if isinstance(device, Operator):
            return device.answer(m)
    return None


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
    refusal = name + " \\{arg} is not modelled here (\\MaxTime, \\BreakFlag)"
    positional, named = split_args(compiler, node, args_node, {"MAXTIME", "BREAKFLAG"}, refusal)
    if len(positional) != 2 + keys:
        what = "an answer variable, a text and five function keys" if keys else "an answer variable and a text"
        compiler.fail(node, f"{name} takes {what} ({len(positional)} arguments given)")
    for key in ("MAXTIME", "BREAKFLAG"):
        if key in named and named[key] is None:
            compiler.fail(node, f"{name} \\{key.title()} needs a value")
    store, where = compiler.lvalue(positional[0]), compiler.where(node)
    prompt, labels = compiler.expr(positional[1]), [compiler.expr(p) for p in positional[2:]]
    max_time = compiler.expr(named["MAXTIME"]) if "MAXTIME" in named else None
    flag = compiler.lvalue(named["BREAKFLAG"]) if "BREAKFLAG" in named else None

    def run(fr):
        m = fr.m
        _show(m, prompt(fr), where, name)
        texts = [label(fr) for label in labels]
        if any(not isinstance(t, str) for t in texts):
            raise RunError(f"{where}: {name}: each function key's text is a string (stEmpty: no key)")
        answer = _operator_answer(m)
        if answer is None:
            if max_time is None:
                raise RunError(
                    f"{where}: {name} waits for the operator's answer and no operator answers in this run "
                    f"(codegen run has none): give {name} \\MaxTime to go on without an answer"
                )
            m.elapse(num(max_time(fr), where), where)
            error = errors.RapidError(errors.ERROR_NUMBERS["ERR_TP_MAXTIME"], f"{where}: {name} \\MaxTime passed")
            if flag is None:
                raise error
            flag(fr, f32(error.errno))
            return
        if not math.isfinite(answer):
            raise RunError(f"{where}: {name}: the operator's answer is not a number")
        if keys and (answer != int(answer) or not 1 <= answer <= keys or not texts[int(answer) - 1]):
            shown = [i + 1 for i, t in enumerate(texts) if t]
            raise RunError(f"{where}: {name}: the operator's answer {answer:g} is not one of the keys {shown}")
        if flag is not None:
            flag(fr, f32(0))
        store(fr, f32(answer))

    return run


SPECIAL = {
    "TPREADFK": lambda compiler, node, args_node: _read(compiler, node, args_node, 5),
    "TPREADNUM": lambda compiler, node, args_node: _read(compiler, node, args_node, 0),
}
BUILTINS = {"TPWRITE": tp_write, "TPERASE": tp_erase}
