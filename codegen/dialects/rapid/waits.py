"""RAPID instructions compiled from their argument nodes: WaitUntil, WaitTime, WaitRob, BookErrNo, SetDO, WaitDI."""

from __future__ import annotations

from collections.abc import Callable

from lark import Tree

from codegen.dialects.core.source import Src
from codegen.dialects.core.values import RunError
from codegen.dialects.rapid import errors
from codegen.dialects.rapid.arguments import split_args
from codegen.dialects.rapid.builtins import num

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
    positional, named = split_args(compiler, node, args_node, {"INPOS", "MAXTIME", "TIMEFLAG", "POLLRATE"})
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


# SetDO Signal, Value and WaitDI Signal, Value [\MaxTime] [\TimeFlag] (RAPID instructions, as recalled):
# the signal is a digital output or input of the controller's I/O configuration (EIO), named as written;
# the program does not declare it. SetDO sets the output when the instruction runs (after a fine point:
# once the arm stands there); WaitDI waits until the input has the value, with \MaxTime as WaitUntil's.
def _signal(compiler, node, arg) -> str:
    if not (isinstance(arg, Tree) and arg.data == "var"):
        compiler.fail(node, f"{node.children[0]}: the signal is a name of the I/O configuration")
    return str(arg.children[0])


def _digital(value, where: str) -> bool:
    number = num(value, where)
    if number not in (0, 1):
        raise RunError(f"{where}: a digital signal's value is 0 or 1, got {number:g}")
    return bool(number)


def set_do(compiler, node, args_node) -> Callable:
    positional, _named = split_args(compiler, node, args_node, set())
    if len(positional) != 2:
        compiler.fail(node, "SetDO takes a signal and a value")
    name, value, where = _signal(compiler, node, positional[0]), compiler.expr(positional[1]), compiler.where(node)
    return lambda fr: fr.m.set_output(name, _digital(value(fr), where), where)


def wait_di(compiler, node, args_node) -> Callable:
    positional, named = split_args(compiler, node, args_node, {"MAXTIME", "TIMEFLAG"})
    if len(positional) != 2:
        compiler.fail(node, "WaitDI takes a signal and a value")
    name, value, where = _signal(compiler, node, positional[0]), compiler.expr(positional[1]), compiler.where(node)
    max_time = _value(compiler, node, named, "MAXTIME")
    flag = compiler.lvalue(named["TIMEFLAG"]) if named.get("TIMEFLAG") is not None and max_time is not None else None

    def run(fr):
        want, m = _digital(value(fr), where), fr.m
        came = m.signals.get(name, False) == want
        if not came:
            seconds = None if max_time is None else num(max_time(fr), where)
            came = m.wait_for(lambda: m.signals.get(name, False) == want, where, seconds, "WaitDI")
            if flag is not None:
                flag(fr, not came)
            elif not came:
                raise errors.wait_maxtime(where, "WaitDI", seconds)
        elif flag is not None:
            flag(fr, False)

    return run


# SetGO Signal, Value and the functions GInput(Signal), GOutput(Signal), DInput(Signal) (RAPID instructions and
# functions, as recalled): a group of digital signals of the I/O configuration read or written as one
# number (GInput: up to 23 bits, a num; the group's width is the configuration's: 16 here is checked
# against nothing but the value's range), a digital input as 0 or 1. An input's value is what the
# devices set, or a device's live value (an encoder's count).
GROUP_MAX = 2**23


def set_go(compiler, node, args_node) -> Callable:
    positional, _named = split_args(compiler, node, args_node, set())
    if len(positional) != 2:
        compiler.fail(node, "SetGO takes a signal and a value")
    name, value, where = _signal(compiler, node, positional[0]), compiler.expr(positional[1]), compiler.where(node)

    def run(fr):
        number = num(value(fr), where)
        if number != int(number) or not 0 <= number < GROUP_MAX:
            raise RunError(f"{where}: SetGO {name}: {number:g} is not a whole number in 0..{GROUP_MAX - 1}")
        fr.m.outputs[name] = int(number)
        fr.m.output_written(where)

    return run


def signal_function(compiler, node, name: str, args_node):
    """GInput(signal) and DInput(signal) as expression sources, else None."""
    key = name.upper()
    if key not in ("GINPUT", "DINPUT", "GOUTPUT"):
        return None
    positional, _named = split_args(compiler, node, args_node, set())
    if len(positional) != 1:
        compiler.fail(node, f"{name} takes one signal")
    signal = _signal(compiler, node, positional[0])
    if key == "GINPUT":

        def read(fr):
            value = fr.m.input_signal(signal, 0)
            return float(int(value))
    elif key == "GOUTPUT":  # what the program last wrote with SetGO (0 before)

        def read(fr):
            return float(fr.m.outputs.get(signal, 0))
    else:

        def read(fr):
            return float(bool(fr.m.input_signal(signal)))

    return Src(f"{compiler.const(read)}(fr)")


SPECIAL = {
    "SETGO": set_go,
    "WAITUNTIL": wait_until,
    "WAITTIME": wait_time,
    "WAITROB": wait_rob,
    "BOOKERRNO": book_errno,
    "SETDO": set_do,
    "WAITDI": wait_di,
}
