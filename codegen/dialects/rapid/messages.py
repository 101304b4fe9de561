"""RAPID operator messages: ErrWrite (the event log), UIMsgBox and UIMessageBox (boxes the operator answers)."""

from __future__ import annotations

from collections.abc import Callable

from codegen.dialects.core.values import RunError, f32
from codegen.dialects.rapid.arguments import split_args
from codegen.dialects.rapid.pendant import press

# ErrWrite [\W] | [\I] Header Reason [\RL2] [\RL3] [\RL4] (ABB, "Technical reference manual - RAPID
# Instructions, Functions and Data types", ErrWrite, as recalled; the text was not found during this
# work, so the limits are uncertain): the header has at most 46 characters, each reason line is a
# string (80 characters at most), and Reason with \RL2-\RL4 together at most 195 characters. The
# message goes to the event log (\W: a warning, \I: information, both only stored in the log; without
# them it is also shown on the FlexPendant); program execution goes on. Here every form is recorded as
# an operator message (its reason line): what the operator reads when the program then stops.
ERRWRITE_HEADER_MAX = 46
ERRWRITE_LINE_MAX = 80
ERRWRITE_TOTAL_MAX = 195

# UIMsgBox's data (buttondata, icondata, btnres), values as recalled from the same manual (uncertain).
BUTTONS = {"BTNNONE": -1, "BTNOK": 0, "BTNABRTRTRYIGN": 1, "BTNOKCANCEL": 2, "BTNRETRYCANCEL": 3, "BTNYESNO": 4}
BUTTONS["BTNYESNOCANCEL"] = 5
ICONS = {"ICONNONE": 0, "ICONINFO": 1, "ICONWARNING": 2, "ICONERROR": 3}
RESULTS = {"RESUNKWN": 0, "RESOK": 1, "RESABORT": 2, "RESRETRY": 3, "RESIGNORE": 4, "RESCANCEL": 5}
RESULTS |= {"RESYES": 6, "RESNO": 7}
# The answer of the interpreter's operator, who presses a box's first button at once.
FIRST_BUTTON = {0: "RESOK", 1: "RESABORT", 2: "RESOK", 3: "RESRETRY", 4: "RESYES", 5: "RESYES"}
PREDEFINED_VALUES = {name: f32(value) for name, value in (BUTTONS | ICONS | RESULTS).items()}


def _text(value, where: str, what: str, limit: int) -> str:
    if not isinstance(value, str):
        raise RunError(f"{where}: {what} must be a string")
    if len(value) > limit:
        raise RunError(f"{where}: {what} has {len(value)} characters, at most {limit}")
    return value


def err_write(fr, args, kwargs, where: str) -> None:
    if len(args) != 2:
        raise RunError(f"{where}: ErrWrite takes a header and a reason ({len(args)} arguments given)")
    if {"W", "I"} <= set(kwargs) or set(kwargs) - {"W", "I", "RL2", "RL3", "RL4"}:
        raise RunError(f"{where}: ErrWrite takes \\W or \\I, and \\RL2, \\RL3, \\RL4")
    _text(args[0], where, "ErrWrite header", ERRWRITE_HEADER_MAX)
    lines = [_text(args[1], where, "ErrWrite reason", ERRWRITE_LINE_MAX)]
    for key in ("RL2", "RL3", "RL4"):
        if key in kwargs:
            lines.append(_text(kwargs[key], where, f"ErrWrite \\{key}", ERRWRITE_LINE_MAX))
    total = sum(map(len, lines))
    if total > ERRWRITE_TOTAL_MAX:
        raise RunError(f"{where}: ErrWrite reason lines have {total} characters, at most {ERRWRITE_TOTAL_MAX}")
    fr.m.message(lines[0])


UIMSGBOX_ARGS = {"HEADER", "MSGLINE2", "MSGLINE3", "MSGLINE4", "MSGLINE5", "WRAP", "BUTTONS", "ICON", "RESULT"}


def ui_msg_box(compiler, node, args_node) -> Callable:
    """UIMsgBox [\\Header] MsgLine1 [\\MsgLine2..5] [\\Wrap] [\\Buttons] [\\Icon] [\\Result]: the first line
    becomes an operator message; the box blocks until the operator answers, which the interpreter's
    operator does at once with the first button (\\Result gets its btnres). Other arguments (\\MaxTime,
    \\DIBreak, \\BtnArray, ...) are not modelled and are refused."""
    positional, named = split_args(compiler, node, args_node, UIMSGBOX_ARGS, "UIMsgBox \\{arg} is not supported here")
    if len(positional) != 1:
        compiler.fail(node, "UIMsgBox takes one message line (MsgLine1)")
    line, where = compiler.expr(positional[0]), compiler.where(node)
    buttons = compiler.expr(named["BUTTONS"]) if named.get("BUTTONS") is not None else None
    result = compiler.lvalue(named["RESULT"]) if named.get("RESULT") is not None else None

    def run(fr):
        text = _text(line(fr), where, "UIMsgBox message line", ERRWRITE_LINE_MAX)
        fr.m.message(text)
        chosen = int(float(buttons(fr))) if buttons is not None else BUTTONS["BTNOK"]
        if chosen not in FIRST_BUTTON:
            raise RunError(f"{where}: UIMsgBox without a button the operator can press waits forever")
        if result is not None:
            result(fr, PREDEFINED_VALUES[FIRST_BUTTON[chosen]])

    return run


# UIMessageBox ([\Header] [\Message] | [\MsgArray] [\Wrap] [\Buttons] | [\BtnArray] [\DefaultBtn] [\Icon]
# [\Image] [\MaxTime] [\DIBreak] [\DIPassive] [\DOBreak] [\DOPassive] [\PersBoolBreak] [\PersBoolPassive]
# [\BreakFlag] [\UIActiveSignal]) returns the btnres of the button pressed, or with \BtnArray the number of the
# button (same manual, as recalled). The message lines are recorded as one operator message; the run's operator
# answers (codegen run --answer: a button's number or its label), else presses the first button at once, as for
# UIMsgBox, so no break condition (\MaxTime, \DIBreak, ...) is reached and \BreakFlag is not written.
BUTTON_LABELS = {
    0: ["OK"], 1: ["Abort", "Retry", "Ignore"], 2: ["OK", "Cancel"], 3: ["Retry", "Cancel"], 4: ["Yes", "No"],
    5: ["Yes", "No", "Cancel"],
}  # fmt: skip
BUTTON_RESULTS = {0: ["RESOK"], 1: ["RESABORT", "RESRETRY", "RESIGNORE"], 2: ["RESOK", "RESCANCEL"]}
BUTTON_RESULTS |= {3: ["RESRETRY", "RESCANCEL"], 4: ["RESYES", "RESNO"], 5: ["RESYES", "RESNO", "RESCANCEL"]}
UIMESSAGEBOX_ARGS = frozenset({
    "HEADER", "MESSAGE", "MSGARRAY", "WRAP", "BUTTONS", "BTNARRAY", "DEFAULTBTN", "ICON", "IMAGE", "MAXTIME",
    "DIBREAK", "DIPASSIVE", "DOBREAK", "DOPASSIVE", "PERSBOOLBREAK", "PERSBOOLPASSIVE", "BREAKFLAG", "UIACTIVESIGNAL",
})  # fmt: skip


def ui_message_box(fr, args, kwargs, where):
    if args or set(kwargs) - UIMESSAGEBOX_ARGS:
        extra = sorted(set(kwargs) - UIMESSAGEBOX_ARGS)
        named = f", not \\{extra[0].title()}" if extra else ""
        raise RunError(f"{where}: UIMessageBox takes only optional arguments{named}")
    if ("MESSAGE" in kwargs and "MSGARRAY" in kwargs) or ("BUTTONS" in kwargs and "BTNARRAY" in kwargs):
        raise RunError(f"{where}: UIMessageBox: \\Message or \\MsgArray, \\Buttons or \\BtnArray (alternatives)")
    lines = kwargs["MSGARRAY"] if "MSGARRAY" in kwargs else [kwargs.get("MESSAGE", "")]
    if not isinstance(lines, list) or any(not isinstance(line, str) for line in lines):
        raise RunError(f"{where}: UIMessageBox: the message lines are strings")
    fr.m.message(" ".join(line for line in lines if line))
    if "BTNARRAY" in kwargs:
        labels = kwargs["BTNARRAY"]
        if not isinstance(labels, list) or any(not isinstance(label, str) for label in labels):
            raise RunError(f"{where}: UIMessageBox \\BtnArray is an array of strings")
        shown = [label or None for label in labels]
        if not any(shown):
            raise RunError(f"{where}: UIMessageBox without a button the operator can press waits forever")
        return f32(_pressed(fr.m, shown, where))
    chosen = int(float(kwargs.get("BUTTONS", BUTTONS["BTNOK"])))
    if chosen not in BUTTON_LABELS:
        raise RunError(f"{where}: UIMessageBox without a button the operator can press waits forever")
    return PREDEFINED_VALUES[BUTTON_RESULTS[chosen][_pressed(fr.m, BUTTON_LABELS[chosen], where) - 1]]


def _pressed(m, labels: list, where: str) -> int:
    """The number (1...) of the button the run's operator presses: its answer, or the first button shown."""
    answer = press(m, labels)
    if answer is None:
        return next(i for i, label in enumerate(labels, 1) if label is not None)
    pressable = isinstance(answer, int | float) and not isinstance(answer, bool) and 1 <= answer <= len(labels)
    if not pressable or labels[int(answer) - 1] is None:
        names = ", ".join(f"{i} {label}" for i, label in enumerate(labels, 1) if label is not None)
        raise RunError(f"{where}: UIMessageBox: the operator's answer {answer!r} is not one of the buttons ({names})")
    return int(answer)
