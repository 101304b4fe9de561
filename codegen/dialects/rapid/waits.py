"""RAPID instructions compiled from their argument nodes: WaitUntil, WaitTime, WaitRob, BookErrNo."""

from __future__ import annotations

from collections.abc import Callable

from lark import Tree

from codegen.dialects.core.values import RunError
from codegen.dialects.rapid import errors
from codegen.dialects.rapid.arguments import WAIT_DISPLAY, split_args
from codegen.dialects.rapid.types import num

# Sources: ABB, "Technical reference manual - RAPID Instructions, Functions and Data types", WaitUntil,
# WaitTime and WaitRob, as recalled (the manual's text was not found during this work):
# - WaitUntil [\InPos] Cond [\MaxTime] [\TimeFlag] [\PollRate]: \InPos: the robot and external axes
#   stand still before the condition is first tested; \MaxTime (s): when it passes first, the error
#   handler is called with ERR_WAIT_MAXTIME, and without one the execution stops; \TimeFlag (bool,
#   INOUT): TRUE when the time ran out, and then running out is not an error (ignored without
#   \MaxTime); \PollRate (s, default 0.1, at least 0.04): how often the condition is tested;
# - WaitTime [\InPos] Time: with \InPos the robot stands still before the time starts to count; Time >= 0;
# - WaitRob \InPos | \ZeroSpeed: wait until the robot has reached its stop point (\InPos) or has zero
#   speed (\ZeroSpeed); the interpreter has no servo lag: both wait for the end of the commanded motion.
POLL_RATE_MIN = 0.04


def _value(compiler, node, named: dict, key: str):
    if key not in named:
        return None
    if named[key] is None:
        compiler.fail(node, f"\\{key.title()} needs a value (\\{key.title()}:=...)")
    return compiler.expr(named[key])


def wait_until(compiler, node, args_node) -> Callable:
    switches = {"INPOS", "MAXTIME", "TIMEFLAG", "POLLRATE", *WAIT_DISPLAY}
    positional, named = split_args(compiler, node, args_node, switches)
    if len(positional) != 1:
        compiler.fail(node, "WaitUntil takes one condition")
    cond, where = compiler.expr(positional[0]), compiler.where(node)
    in_pos = "INPOS" in named
    max_time = _value(compiler, node, named, "MAXTIME")
    poll_rate = _value(compiler, node, named, "POLLRATE")
    if "TIMEFLAG" in named and named["TIMEFLAG"] is None:
        compiler.fail(node, "\\TimeFlag needs a bool variable (\\TimeFlag:=flag)")
    flag = compiler.lvalue(named["TIMEFLAG"]) if "TIMEFLAG" in named and max_time is not None else None

    def run(fr):
        m = fr.m
        if poll_rate is not None and num(poll_rate(fr), where) < POLL_RATE_MIN:
            raise RunError(f"{where}: WaitUntil \\PollRate below {POLL_RATE_MIN} s")
        if in_pos:
            m.arrive(where)
        if max_time is None:
            if not cond(fr):
                m.wait_for(lambda: cond(fr), where, None, "WaitUntil")
            return None
        seconds = num(max_time(fr), where)
        came = bool(cond(fr)) or m.wait_for(lambda: cond(fr), where, seconds, "WaitUntil")
        if flag is not None:
            flag(fr, not came)
        elif not came:
            raise errors.wait_maxtime(where, "WaitUntil", seconds)
        return None

    return run


def wait_time(compiler, node, args_node) -> Callable:
    positional, named = split_args(compiler, node, args_node, {"INPOS"})
    if len(positional) != 1:
        compiler.fail(node, "WaitTime takes one time in seconds")
    seconds, where, in_pos = compiler.expr(positional[0]), compiler.where(node), "INPOS" in named

    def run(fr):
        time = num(seconds(fr), where)
        if not time >= 0:
            raise RunError(f"{where}: WaitTime {time:g} s: the time must be at least 0 s")
        if in_pos:
            fr.m.arrive(where)
        fr.m.elapse(time, where)

    return run


def wait_rob(compiler, node, args_node) -> Callable:
    positional, named = split_args(compiler, node, args_node, {"INPOS", "ZEROSPEED"})
    if positional or len(named) != 1 or any(v is not None for v in named.values()):
        compiler.fail(node, "WaitRob takes \\InPos or \\ZeroSpeed")
    where = compiler.where(node)
    return lambda fr: fr.m.arrive(where)


def book_errno(compiler, node, args_node) -> Callable:
    """BookErrNo errnum_variable: the variable gets a new error number the program may RAISE."""
    positional, _named = split_args(compiler, node, args_node, set())
    if len(positional) != 1 or not (isinstance(positional[0], Tree) and positional[0].data == "var"):
        compiler.fail(node, "BookErrNo takes an errnum variable")
    store, where = compiler.lvalue(positional[0]), compiler.where(node)
    return lambda fr: store(fr, errors.book_errno(fr, where))


SPECIAL = {
    "WAITUNTIL": wait_until,
    "WAITTIME": wait_time,
    "WAITROB": wait_rob,
    "BOOKERRNO": book_errno,
}
