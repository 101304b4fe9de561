"""RAPID I/O: Set, Reset, SetDO, PulseDO, SetGO, SetAO, WaitDI, WaitDO, AliasIO, DInput()..., signals read as values."""

from __future__ import annotations

from collections.abc import Callable

from lark import Tree

from codegen.dialects.core.machine import SignalEvent
from codegen.dialects.core.source import Src
from codegen.dialects.core.values import Record, RunError, f32
from codegen.dialects.rapid import errors
from codegen.dialects.rapid.arguments import WAIT_DISPLAY, split_args
from codegen.dialects.rapid.types import SIGNAL_TYPES, num

# Sources: ABB, "Technical reference manual - RAPID Instructions, Functions and Data types" (RobotWare 6/7):
# Set, Reset, SetDO, PulseDO, InvertDO, SetGO, SetAO, WaitDI, WaitDO, AliasIO, and the functions DInput, DOutput,
# GInput, GOutput, AInput, AOutput, TestDI, ValidIO; data types signaldi/signaldo/signalgi/signalgo/signalai/
# signalao. As recalled (the manual's text was not readable during this work):
# - a signal is named in the controller's I/O configuration (EIO), not in the program; a program may also declare
#   a signal variable and connect it to a configured signal with AliasIO; a signal used in an expression has its
#   value (a digital one 0 or 1);
# - Set / Reset: the digital output to 1 / 0; SetDO [\SDelay] [\Sync] Signal, Value: to Value (0 or 1), \SDelay:
#   after that many seconds while the program goes on (\Sync: the program waits for the physical change: no time
#   here); PulseDO [\High] [\PLength] Signal: a pulse of \PLength s (default 0.2 s) while the program goes on;
#   InvertDO: the inverse; SetGO / SetAO: a group or analog output's value;
# - WaitDI / WaitDO Signal, Value [\MaxTime] [\TimeFlag]: wait until the signal has the value, \MaxTime as
#   WaitUntil's (ERR_WAIT_MAXTIME, or \TimeFlag TRUE); WaitGI / WaitGO Signal, [\NOTEQ] | [\LT] | [\GT] Value
#   [\MaxTime] [\TimeFlag]: the same for a group's whole number, equal to the value unless a switch asks for
#   not equal, less or greater (the switches not confirmed in the manual's text);
# - TestDI(Signal): TRUE when the digital input is 1; ValidIO: TRUE (every signal here is valid).
# Here a signal the program uses but does not declare is simulated I/O: inputs are what the devices (or codegen
# run --signal) set, FALSE / 0 otherwise; outputs are recorded in the trace (SignalEvent: digital ones).
PULSE_S = 0.2

# Which argument of an instruction or function is a signal, and of which kind (for the names a program uses).
SIGNAL_ARGS = {
    "SET": "DO", "RESET": "DO", "SETDO": "DO", "PULSEDO": "DO", "INVERTDO": "DO", "WAITDO": "DO", "DOUTPUT": "DO",
    "WAITDI": "DI", "WAITGI": "GI", "WAITGO": "GO", "DINPUT": "DI", "TESTDI": "DI", "ISIGNALDI": "DI", "SEARCHL": "DI",
    "MOVEJDO": "DO", "MOVELDO": "DO", "SETGO": "GO", "GOUTPUT": "GO", "GINPUT": "GI",
    "SETAO": "AO", "AOUTPUT": "AO", "AINPUT": "AI",
}  # fmt: skip
SIGNAL_INDEX = {"MOVEJDO": 4, "MOVELDO": 4}  # the signal's place among the positional arguments (else the first)
KIND_NAMES = {"DI": "digital input", "DO": "digital output", "GI": "group input", "GO": "group output",
              "AI": "analog input", "AO": "analog output"}  # fmt: skip
GROUP_MAX = 2**23


def signal_uses(tree) -> list[tuple[str, str, object]]:
    """(name, kind, token) of every signal argument (a plain name) of the signal instructions and functions."""
    found = []
    for node in tree.iter_subtrees():
        if node.data not in ("proc_call", "call"):
            continue
        name, args_node = node.children[0], node.children[1]
        kind = SIGNAL_ARGS.get(str(name).upper())
        if kind is None or args_node is None:
            continue
        positional = [a for a in args_node.children if not (isinstance(a, Tree) and a.data == "opt_arg")]
        at = SIGNAL_INDEX.get(str(name).upper(), 0)
        arg = positional[at] if len(positional) > at else None
        if isinstance(arg, Tree) and arg.data == "var":
            found.append((str(arg.children[0]), kind, arg.children[0]))
    return found


def signal_ref(compiler, node, arg) -> Callable:
    """fr -> the configured signal's name that an argument names: an undeclared name (simulated I/O, as the
    program first spells it), or a declared signal variable connected with AliasIO."""
    if not (isinstance(arg, Tree) and arg.data == "var"):
        compiler.fail(node, f"{node.children[0]}: the signal is a name of the I/O configuration")
    written = str(arg.children[0])
    key = compiler.data_key(written)
    if key in compiler.data_types and compiler.data_types[key] in SIGNAL_TYPES:
        where = compiler.where(node)

        def connected(fr):
            value = fr.m.globals.get(key)
            if not isinstance(value, Record) or not value.get("NAME"):
                raise RunError(f"{where}: signal variable {written} is not connected to a signal (AliasIO)")
            return value["NAME"]

        return connected
    if key in compiler.data_types:
        compiler.fail(arg, f"{written} is program data, not a signal")
    name = compiler.signal_names.get(written.upper(), written)
    return lambda fr: name


def _digital(value, where: str) -> bool:
    number = num(value, where)
    if number not in (0, 1):
        raise RunError(f"{where}: a digital signal's value is 0 or 1, got {number:g}")
    return bool(number)


def _positional(compiler, node, args_node, count: int, what: str, switches=frozenset()):
    positional, named = split_args(compiler, node, args_node, set(switches))
    if len(positional) != count:
        compiler.fail(node, f"{node.children[0]} takes {what}")
    return positional, named


def _later(m, name: str, value: bool, where: str, delay: float) -> None:
    """A digital output that changes delay seconds from now (\\SDelay, the end of a pulse)."""
    m.signals[name] = bool(value)
    t = m.clock + delay
    line = int(where.split(":")[1]) if where.count(":") >= 2 else 0
    m.trace.outputs.append(SignalEvent(name, bool(value), line, t, m.arm_until > t, len(m.trace.moves), m.tool_pose()))


def set_reset(value: bool):
    def compile_(compiler, node, args_node) -> Callable:
        positional, _ = _positional(compiler, node, args_node, 1, "one digital output")
        signal, where = signal_ref(compiler, node, positional[0]), compiler.where(node)
        return lambda fr: fr.m.set_output(signal(fr), value, where)

    return compile_


def set_do(compiler, node, args_node) -> Callable:
    positional, named = _positional(compiler, node, args_node, 2, "a signal and a value", {"SDELAY", "SYNC"})
    signal, value, where = signal_ref(compiler, node, positional[0]), compiler.expr(positional[1]), compiler.where(node)
    delay = compiler.expr(named["SDELAY"]) if named.get("SDELAY") is not None else None

    def run(fr):
        on = _digital(value(fr), where)
        if delay is None:
            fr.m.set_output(signal(fr), on, where)
        else:
            _later(fr.m, signal(fr), on, where, num(delay(fr), where))

    return run


def pulse_do(compiler, node, args_node) -> Callable:
    positional, named = _positional(compiler, node, args_node, 1, "one digital output", {"HIGH", "PLENGTH"})
    signal, where = signal_ref(compiler, node, positional[0]), compiler.where(node)
    length = compiler.expr(named["PLENGTH"]) if named.get("PLENGTH") is not None else None

    def run(fr):
        m, name = fr.m, signal(fr)
        seconds = PULSE_S if length is None else num(length(fr), where)
        if not 0.001 <= seconds <= 2000:
            raise RunError(f"{where}: PulseDO \\PLength {seconds:g} s: 0.001 to 2000 s")
        m.set_output(name, True, where)
        _later(m, name, False, where, seconds)
        m.state.pulses[name] = m.clock + seconds

    return run


def invert_do(compiler, node, args_node) -> Callable:
    positional, _ = _positional(compiler, node, args_node, 1, "one digital output")
    signal, where = signal_ref(compiler, node, positional[0]), compiler.where(node)

    def run(fr):
        name = signal(fr)
        fr.m.set_output(name, not output_value(fr.m, name), where)

    return run


def output_value(m, name: str) -> bool:
    pulses = m.state.pulses
    if name in pulses and m.clock < pulses[name]:
        return True
    return bool(m.signals.get(name, False))


def set_go(compiler, node, args_node) -> Callable:
    positional, _ = _positional(compiler, node, args_node, 2, "a signal and a value", {"SDELAY"})
    signal, value, where = signal_ref(compiler, node, positional[0]), compiler.expr(positional[1]), compiler.where(node)

    def run(fr):
        number = num(value(fr), where)
        name = signal(fr)
        if number != int(number) or not 0 <= number < GROUP_MAX:
            raise RunError(f"{where}: SetGO {name}: {number:g} is not a whole number in 0..{GROUP_MAX - 1}")
        fr.m.outputs[name] = int(number)
        fr.m.output_written(where)

    return run


def set_ao(compiler, node, args_node) -> Callable:
    positional, _ = _positional(compiler, node, args_node, 2, "a signal and a value")
    signal, value, where = signal_ref(compiler, node, positional[0]), compiler.expr(positional[1]), compiler.where(node)

    def run(fr):
        fr.m.outputs[signal(fr)] = num(value(fr), where)
        fr.m.output_written(where)

    return run


# A group wait's comparison by its switch (none: equal).
GROUP_TESTS = {None: lambda have, want: have == want, "NOTEQ": lambda have, want: have != want,
               "LT": lambda have, want: have < want, "GT": lambda have, want: have > want}  # fmt: skip
WAIT_KEYWORDS = {"DI": "WaitDI", "DO": "WaitDO", "GI": "WaitGI", "GO": "WaitGO"}


def wait_signal(kind: str):
    """WaitDI / WaitDO / WaitGI / WaitGO Signal, Value [\\MaxTime] [\\TimeFlag] (a group's: \\NOTEQ, \\LT, \\GT)."""
    keyword = WAIT_KEYWORDS[kind]
    group = kind in ("GI", "GO")

    def compile_(compiler, node, args_node) -> Callable:
        switches = {"MAXTIME", "TIMEFLAG", *WAIT_DISPLAY, *(("NOTEQ", "LT", "GT") if group else ())}
        positional, named = _positional(compiler, node, args_node, 2, "a signal and a value", switches)
        asked = [key for key in ("NOTEQ", "LT", "GT") if key in named]
        if len(asked) > 1:
            compiler.fail(node, f"{keyword} takes one of \\NOTEQ, \\LT and \\GT")
        test = GROUP_TESTS[asked[0] if asked else None]
        if group:
            return _wait_group(compiler, node, positional, named, keyword, kind, test)
        signal, value = signal_ref(compiler, node, positional[0]), compiler.expr(positional[1])
        where = compiler.where(node)
        if "MAXTIME" in named and named["MAXTIME"] is None:
            compiler.fail(node, "\\MaxTime needs a value (\\MaxTime:=...)")
        max_time = compiler.expr(named["MAXTIME"]) if named.get("MAXTIME") is not None else None
        flag = compiler.lvalue(named["TIMEFLAG"]) if named.get("TIMEFLAG") is not None and max_time else None

        def run(fr):
            want, m, name = _digital(value(fr), where), fr.m, signal(fr)

            def now() -> bool:
                have = bool(m.input_signal(name)) if kind == "DI" else output_value(m, name)
                return have == want

            _await(fr, now, where, keyword, max_time, flag)

        return run

    return compile_


def _await(fr, now: Callable[[], bool], where: str, keyword: str, max_time, flag) -> None:
    """Wait until now() holds: at most \\MaxTime, then ERR_WAIT_MAXTIME, or \\TimeFlag set and the program goes on."""
    came = now()
    if not came:
        seconds = None if max_time is None else num(max_time(fr), where)
        came = fr.m.wait_for(now, where, seconds, keyword)
        if flag is None and not came:
            raise errors.wait_maxtime(where, keyword, seconds)
    if flag is not None:
        flag(fr, not came)


def _wait_group(compiler, node, positional, named, keyword: str, kind: str, test) -> Callable:
    """A group input's (or output's) wait: its whole number compared with the value until the test holds."""
    signal, value, where = signal_ref(compiler, node, positional[0]), compiler.expr(positional[1]), compiler.where(node)
    if "MAXTIME" in named and named["MAXTIME"] is None:
        compiler.fail(node, "\\MaxTime needs a value (\\MaxTime:=...)")
    max_time = compiler.expr(named["MAXTIME"]) if named.get("MAXTIME") is not None else None
    flag = compiler.lvalue(named["TIMEFLAG"]) if named.get("TIMEFLAG") is not None and max_time else None
    read = reader(kind, signal)

    def run(fr):
        want = num(value(fr), where)
        if want != int(want) or not 0 <= want < GROUP_MAX:
            raise RunError(f"{where}: {keyword} {signal(fr)}: {want:g} is not a whole number in 0..{GROUP_MAX - 1}")

        def now() -> bool:
            return test(float(read(fr)), want)

        _await(fr, now, where, keyword, max_time, flag)

    return run


def move_do(name: str):
    """MoveJDO / MoveLDO ToPoint, Speed, Zone, Tool [\\WObj], Signal, Value: the move, and the digital output set when
    the arm reaches the point (RAPID instructions, MoveLDO, as recalled: at a stop point, or in the middle of the
    corner path of a fly-by point: here when the move ends either way)."""
    move = name[:-2]  # MOVEJ / MOVEL

    def compile_(compiler, node, args_node) -> Callable:
        positional, named = _positional(compiler, node, args_node, 6, "ToPoint, Speed, Zone, Tool, Signal and Value",
                                        {"WOBJ"})  # fmt: skip
        if named.get("WOBJ", True) is None:
            compiler.fail(node, f"{node.children[0]} \\WObj needs a value (\\WObj:=...)")
        parts = [compiler.expr(n) for n in positional[:4]]
        wobj = compiler.expr(named["WOBJ"]) if "WOBJ" in named else None
        signal, value = signal_ref(compiler, node, positional[4]), compiler.expr(positional[5])
        where, run_move = compiler.where(node), compiler.builtins[move]

        def run(fr):
            m = fr.m
            kwargs = {"WOBJ": wobj(fr)} if wobj is not None else {}
            run_move(fr, [p(fr) for p in parts], kwargs, where)
            on = _digital(value(fr), where)
            _later(m, signal(fr), on, where, max(0.0, m.last_move.end_time - m.clock))

        return run

    return compile_


def alias_io(compiler, node, args_node) -> Callable:
    """AliasIO FromSignal, ToSignal: the signal variable ToSignal stands for the configured signal FromSignal (a
    string, or the signal's name)."""
    positional, _ = _positional(compiler, node, args_node, 2, "a configured signal and a signal variable")
    source, target = positional
    if isinstance(source, Tree) and source.data == "var":
        name = compiler.signal_names.get(str(source.children[0]).upper(), str(source.children[0]))
        read = None
    else:
        read, name = compiler.expr(source), None
    if not (isinstance(target, Tree) and target.data == "var"):
        compiler.fail(node, "AliasIO: the second argument is a signal variable")
    key = compiler.data_key(str(target.children[0]))
    kind = compiler.data_types.get(key)
    local = compiler.local_types is not None and key in compiler.local_types
    if kind not in SIGNAL_TYPES or local:
        compiler.fail(target, f"AliasIO: {target.children[0]} is not a signal variable of the module (signaldo...)")
    where = compiler.where(node)

    def run(fr):
        signal = name if read is None else read(fr)
        if not isinstance(signal, str) or not signal:
            raise RunError(f"{where}: AliasIO: the configured signal is a name or a string")
        fr.m.globals[key] = Record(kind, {"NAME": signal})

    return run


def signal_function(compiler, node, name: str, args_node):
    """DInput, DOutput, GInput, GOutput, AInput, AOutput, TestDI, ValidIO as expression sources, else None."""
    key = name.upper()
    if key not in ("GINPUT", "DINPUT", "GOUTPUT", "DOUTPUT", "AINPUT", "AOUTPUT", "TESTDI", "VALIDIO"):
        return None
    positional, _named = split_args(compiler, node, args_node, set())
    if len(positional) != 1:
        compiler.fail(node, f"{name} takes one signal")
    signal = signal_ref(compiler, node, positional[0])
    return Src(f"{compiler.const(reader(key, signal))}(fr)")


def reader(key: str, signal: Callable) -> Callable:
    """fr -> the signal's value as the function (or a signal read as a value) gives it."""
    if key == "VALIDIO":
        return lambda fr: True
    if key == "TESTDI":
        return lambda fr: bool(fr.m.input_signal(signal(fr)))
    if key in ("GINPUT", "GI"):
        return lambda fr: f32(int(fr.m.input_signal(signal(fr), 0)))
    if key in ("GOUTPUT", "GO"):
        return lambda fr: f32(fr.m.outputs.get(signal(fr), 0))
    if key in ("AINPUT", "AI"):
        return lambda fr: f32(fr.m.input_signal(signal(fr), 0.0))
    if key in ("AOUTPUT", "AO"):
        return lambda fr: f32(fr.m.outputs.get(signal(fr), 0.0))
    if key in ("DOUTPUT", "DO"):
        return lambda fr: f32(output_value(fr.m, signal(fr)))
    return lambda fr: f32(bool(fr.m.input_signal(signal(fr))))


SPECIAL = {
    "SET": set_reset(True),
    "RESET": set_reset(False),
    "SETDO": set_do,
    "PULSEDO": pulse_do,
    "INVERTDO": invert_do,
    "SETGO": set_go,
    "SETAO": set_ao,
    "WAITDI": wait_signal("DI"),
    "WAITDO": wait_signal("DO"),
    "WAITGI": wait_signal("GI"),
    "WAITGO": wait_signal("GO"),
    "ALIASIO": alias_io,
    "MOVEJDO": move_do("MOVEJDO"),
    "MOVELDO": move_do("MOVELDO"),
}
