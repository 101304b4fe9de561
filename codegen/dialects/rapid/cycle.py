"""RAPID's view of the controller's run: OpMode, RunMode, CTime, CDate, ExitCycle, StorePath / RestoPath, ErrRaise."""

from __future__ import annotations

import datetime
from collections.abc import Callable

from lark import Token, Tree

from codegen.dialects.core.values import LimitReached, RunError, f32
from codegen.dialects.rapid import errors
from codegen.dialects.rapid.arguments import split_args

# ABB, "Technical reference manual - RAPID Instructions, Functions and Data types" (RobotWare 6), as recalled
# (the text was not readable during this work; values marked so):
# - OpMode() returns a symnum: OP_UNDEF 0, OP_AUTO 1, OP_MAN_PROG 2 (manual reduced speed), OP_MAN_TEST 3
#   (manual full speed); RunMode() RUN_UNDEF 0, RUN_CONT_CYCLE 1, RUN_INSTR_FWD 2, RUN_INSTR_BWD 3, RUN_SIM 4,
#   RUN_STEP_MOVE 5 (values recalled). A run here is in automatic mode and continuous (assumed, as the other
#   controllers' interpreters assume): OpMode() is OP_AUTO, RunMode() RUN_CONT_CYCLE;
# - CTime() the controller's time of day "hh:mm:ss": the run's clock from 00:00:00 at its start (assumed: the
#   controller's real time is not a program's);
# - CDate() the controller's date "yyyy-mm-dd" (the form as recalled): the run starts on RUN_START_DATE (assumed, as
#   CTime's midnight: a run's output does not depend on the day it is run), a day later at each 24 h of its clock;
# - ExitCycle ends the current cycle and moves the program pointer to main's first instruction: in continuous
#   mode the next cycle starts. A run is one cycle: it ends there (cleanly, saying so);
# - StorePath [\KeepSync] keeps the path of the motion under way for a motion in an error handler or a TRAP;
#   RestoPath brings it back. The interpreter stops no motion to resume it: they record the pairing (RestoPath
#   without StorePath, or StorePath twice, is an error, as on the controller);
# - ErrRaise [\W] | [\I] ErrorName, ErrorNo, Title, Str1, Str2, Str3, Str4 [, Str5]: the error named ErrorName
#   (an errnum variable BookErrNo booked, given as a string) is raised in the program, as RAISE does, with a
#   message in the event log (ErrorNo 5000-9999, recalled): the title is recorded as the operator's message.
#   Public programs give seven arguments; whether Str5 is required was not confirmed (six or seven strings taken).
#   The errstr values a program passes for the lines (ERRSTR_EMPTY, ERRSTR_TASK, ...) are texts the controller
#   fills in: here empty, the task's name T_ROB1 (assumed).
OP_MODES = {"OP_UNDEF": 0, "OP_AUTO": 1, "OP_MAN_PROG": 2, "OP_MAN_TEST": 3}
RUN_MODES = {"RUN_UNDEF": 0, "RUN_CONT_CYCLE": 1, "RUN_INSTR_FWD": 2, "RUN_INSTR_BWD": 3, "RUN_SIM": 4}
RUN_MODES["RUN_STEP_MOVE"] = 5
ERRSTR = {"ERRSTR_EMPTY": "", "ERRSTR_ARG": "", "ERRSTR_ARGNAME": "", "ERRSTR_CONTEXT": "", "ERRSTR_UNUSED": ""}
ERRSTR["ERRSTR_TASK"] = "T_ROB1"
PREDEFINED_VALUES = {name: f32(value) for name, value in (OP_MODES | RUN_MODES).items()} | ERRSTR
ERRRAISE_NUMBERS = range(5000, 10000)
RUN_START_DATE = datetime.date(2000, 1, 1)


def _no_arguments(name: str):
    def check(args, kwargs, where):
        if args or kwargs:
            raise RunError(f"{where}: {name} takes no arguments")

    return check


def op_mode(fr, args, kwargs, where):
    _no_arguments("OpMode")(args, kwargs, where)
    return PREDEFINED_VALUES["OP_AUTO"]


def run_mode(fr, args, kwargs, where):
    if args or set(kwargs) - {"MAIN"}:
        raise RunError(f"{where}: RunMode takes \\Main only")
    return PREDEFINED_VALUES["RUN_CONT_CYCLE"]


def c_time(fr, args, kwargs, where):
    _no_arguments("CTime")(args, kwargs, where)
    seconds = int(fr.m.clock)
    return f"{seconds // 3600 % 24:02d}:{seconds // 60 % 60:02d}:{seconds % 60:02d}"


def c_date(fr, args, kwargs, where):
    _no_arguments("CDate")(args, kwargs, where)
    return (RUN_START_DATE + datetime.timedelta(days=int(fr.m.clock) // 86400)).isoformat()


def exit_cycle(fr, args, kwargs, where):
    _no_arguments("ExitCycle")(args, kwargs, where)
    raise LimitReached(f"{where}: ExitCycle: the cycle ends here (the controller starts main again)")


def store_path(fr, args, kwargs, where):
    if args or set(kwargs) - {"KEEPSYNC"}:
        raise RunError(f"{where}: StorePath takes \\KeepSync only")
    if fr.m.state.stored_path:
        raise RunError(f"{where}: StorePath while a path is stored (RestoPath first)")
    fr.m.state.stored_path = True


def resto_path(fr, args, kwargs, where):
    _no_arguments("RestoPath")(args, kwargs, where)
    if not fr.m.state.stored_path:
        raise RunError(f"{where}: RestoPath without a stored path (StorePath first)")
    fr.m.state.stored_path = False


def err_raise(compiler, node, args_node) -> Callable:
    """ErrRaise [\\W] | [\\I] ErrorName, ErrorNo, Title, Str1..Str4 [, Str5] (compiled from its nodes: the name is a
    string naming an errnum variable)."""
    positional, _named = split_args(compiler, node, args_node, {"W", "I"})
    if len(positional) not in (7, 8):
        compiler.fail(node, f"ErrRaise takes ErrorName, ErrorNo, Title and Str1..Str4 [Str5] ({len(positional)} given)")
    name_node = positional[0]
    if not (isinstance(name_node, Tree) and name_node.data == "string"):
        compiler.fail(name_node, "ErrRaise: ErrorName is the errnum variable's name as a string literal")
    name = compiler.string_value(str(name_node.children[0]))
    meta = name_node.meta
    errnum = compiler.expr(Tree("var", [Token("NAME", name, line=meta.line, column=meta.column)], meta))
    number, title = compiler.expr(positional[1]), compiler.expr(positional[2])
    in_handler, where = compiler.in_handler, compiler.where(node)

    def run(fr):
        code = float(number(fr))
        if code != int(code) or int(code) not in ERRRAISE_NUMBERS:
            raise RunError(f"{where}: ErrRaise ErrorNo {code:g}: 5000-9999")
        text = title(fr)
        if not isinstance(text, str):
            raise RunError(f"{where}: ErrRaise: the title is a string")
        fr.m.message(text)
        error = errors.raise_error(fr, errnum(fr), where, name)
        if in_handler:
            error.leaving = fr
        raise error

    return run


BUILTINS = {
    "OPMODE": op_mode,
    "RUNMODE": run_mode,
    "CTIME": c_time,
    "CDATE": c_date,
    "EXITCYCLE": exit_cycle,
    "STOREPATH": store_path,
    "RESTOPATH": resto_path,
}
SPECIAL = {"ERRRAISE": err_raise}
