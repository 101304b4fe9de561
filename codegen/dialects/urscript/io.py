"""URScript's I/O, registers, messages and timing built-ins (the manual's module interfaces, sync, sleep)."""

# The URScript Programming Language, e-Series (SW 5.x, module interfaces), as each function's page states it:
# - the control box's standard digital I/O 0..7 (set_standard_digital_out(n, b), get_standard_digital_in(n),
#   get_standard_digital_out(n)), configurable digital I/O 0..7 (set_configurable_digital_out,
#   get_configurable_digital_in/out), the tool's digital I/O 0..1 (set_tool_digital_out, get_tool_digital_in/
#   out); standard analog inputs and outputs 0..1 (get_standard_analog_in(n), set_standard_analog_out(n, f),
#   f in [0; 1] of the output's range), tool analog inputs 0..1 (get_tool_analog_in(n)).
# - registers: boolean 0..127, integer and float 0..47 (0..23 fieldbus, 24..47 RTDE clients; boolean 64..127);
#   read_input_*_register(n), write_output_*_register(n, v), read_output_*_register(n).
# - textmsg(s1, s2="") writes to the log; popup(s, title, warning, error, blocking) shows the operator a
#   dialog (here a message; a blocking one is confirmed at once).
# - sleep(t): t seconds of the program's (physical) time; sync(): "uses up the remaining 'physical' time a
#   thread has in the current frame" (one 2 ms controller cycle, 500 Hz e-Series); get_steptime(): "the
#   duration of the robot time step in seconds" (0.002 on the e-Series, 500 Hz).
# Modelled: every digital output set is a SignalEvent in the trace (name as below, the moment, whether the
# arm moves); an input no device of the run provides (the vision PC, a gripper, --signal) reads as off / 0 and
# is named in the trace as simulated I/O (Trace.simulated). Analog outputs and registers are stored, not
# traced as events (SignalEvent holds on/off values).

from __future__ import annotations

import math

from codegen.dialects.core.values import RunError, describe, f32, show
from codegen.dialects.urscript import threads
from codegen.dialects.urscript.values import arguments, num, to_text

STEP_TIME_S = 0.002  # one e-Series controller cycle, 500 Hz (URScript manual, get_steptime; thread scheduling)
REGISTER_MAX = 47  # integer and float registers 0..23 fieldbus, 24..47 RTDE clients (URScript manual)
BOOLEAN_REGISTER_MAX = 127  # boolean registers 0..63 fieldbus, 64..127 RTDE clients (URScript manual)
STRING_MAX = 1023  # characters of a string result (URScript manual, str_cat; ur.toml string_max)
# digital I/O banks: name -> the highest port number (the names the trace and --signal use: <bank>[n])
DIGITAL = {"standard": 7, "configurable": 7, "tool": 1}
ANALOG_IN = {"standard": 1, "tool": 1}
ANALOG_OUT = {"standard": 1}
# The deprecated functions of one numbering (Script Directory, e-Series, 17.7 get_digital_in(n), 17.44
# set_digital_out(n, b): "n: integer [0:9] ... The get_standard_digital_in and get_tool_digital_in replace this
# function. Ports 8-9 should be changed to 0-1 for the latter"): still run by the controller; port -> (bank, n)
DEPRECATED_DIGITAL = {n: ("standard", n) for n in range(8)} | {8: ("tool", 0), 9: ("tool", 1)}


def _port(value, top: int, where: str, what: str) -> int:
    if type(value) is not int or not 0 <= value <= top:
        raise RunError(f"{where}: {what} takes an integer 0..{top}, got {show(value)}")
    return value


def read_input(fr, name: str, default=False):
    """An input as the program reads it now; one that nothing of the run provides reads as `default` and is
    named in the trace as simulated I/O."""
    machine = fr.m
    value = machine.input_signal(name, None)
    if value is None:
        machine.simulated(name)
        return default
    return value


def builtins() -> dict:
    table: dict = {}

    for bank, top in DIGITAL.items():

        def set_out(fr, args, kwargs, where, bank=bank, top=top):
            if len(args) == 2 and not kwargs:  # the everyday call, without binding
                n, b = args
            else:
                a = arguments(f"set_{bank}_digital_out", ("n", "b"), {}, args, kwargs, where)
                n, b = a["n"], a["b"]
            if type(n) is not int or not 0 <= n <= top:
                _port(n, top, where, f"set_{bank}_digital_out(n, b)")
            if not isinstance(b, bool):
                raise RunError(f"{where}: set_{bank}_digital_out(n, b) takes True or False, got {describe(b)}")
            fr.m.set_output(f"{bank}_digital_out[{n}]", b, where)

        def get_in(fr, args, kwargs, where, bank=bank, top=top):
            # the input as the controller reads it now (Machine.input_signal: at this cycle where a device
            # switches it with the tool's pose while the arm moves; in a thread's slice, that slice's cycle)
            if len(args) == 1 and not kwargs:
                n = args[0]
            else:
                n = arguments(f"get_{bank}_digital_in", ("n",), {}, args, kwargs, where)["n"]
            if type(n) is not int or not 0 <= n <= top:
                _port(n, top, where, f"get_{bank}_digital_in(n)")
            return bool(read_input(fr, f"{bank}_digital_in[{n}]"))

        def get_out(fr, args, kwargs, where, bank=bank, top=top):
            a = arguments(f"get_{bank}_digital_out", ("n",), {}, args, kwargs, where)
            n = _port(a["n"], top, where, f"get_{bank}_digital_out(n)")
            return bool(fr.m.signals.get(f"{bank}_digital_out[{n}]", False))

        table[f"set_{bank}_digital_out"] = set_out
        table[f"get_{bank}_digital_in"] = get_in
        table[f"get_{bank}_digital_out"] = get_out

    def deprecated(name: str, modern: str, params: tuple):
        def call(fr, args, kwargs, where):
            a = arguments(name, params, {}, args, kwargs, where)
            n = _port(a["n"], max(DEPRECATED_DIGITAL), where, f"{name}({', '.join(params)})")
            bank, port = DEPRECATED_DIGITAL[n]
            return table[modern.format(bank=bank)](fr, [port, *[a[k] for k in params[1:]]], {}, where)

        return call

    for name, modern, params in (
        ("set_digital_out", "set_{bank}_digital_out", ("n", "b")),
        ("get_digital_in", "get_{bank}_digital_in", ("n",)),
        ("get_digital_out", "get_{bank}_digital_out", ("n",)),
    ):
        table[name] = deprecated(name, modern, params)

    for bank, top in ANALOG_IN.items():

        def get_analog(fr, args, kwargs, where, bank=bank, top=top):
            a = arguments(f"get_{bank}_analog_in", ("n",), {}, args, kwargs, where)
            n = _port(a["n"], top, where, f"get_{bank}_analog_in(n)")
            return f32(float(read_input(fr, f"{bank}_analog_in[{n}]", 0.0)))

        table[f"get_{bank}_analog_in"] = get_analog

    def set_standard_analog_out(fr, args, kwargs, where):
        a = arguments("set_standard_analog_out", ("n", "f"), {}, args, kwargs, where)
        n = _port(a["n"], ANALOG_OUT["standard"], where, "set_standard_analog_out(n, f)")
        value = float(num(a["f"], where, "set_standard_analog_out value"))
        if not 0.0 <= value <= 1.0:
            raise RunError(f"{where}: set_standard_analog_out(n, f) takes f in [0; 1] (of the range), got {value:g}")
        fr.m.outputs[f"standard_analog_out[{n}]"] = f32(value)

    def register(kind):
        top = BOOLEAN_REGISTER_MAX if kind == "boolean" else REGISTER_MAX

        def read(fr, args, kwargs, where):
            if kwargs or len(args) != 1:  # the common call, read_input_integer_register(24), takes no binding
                args = [arguments(f"read_input_{kind}_register", ("address",), {}, args, kwargs, where)["address"]]
            index = args[0]
            if type(index) is not int or not 0 <= index <= top:
                _port(index, top, where, f"read_input_{kind}_register")
            key = f"input_{kind}_register_{index}"
            live = fr.m.input_signal(key, None)  # a device's value that changes with time (a counter)
            value = fr.m.inputs.get(key, 0) if live is None else live
            if kind == "boolean":
                return bool(value)
            return int(value) if kind == "integer" else f32(value)

        def write(fr, args, kwargs, where):
            if len(args) == 2 and not kwargs:
                index, value = args
            else:
                a = arguments(f"write_output_{kind}_register", ("address", "value"), {}, args, kwargs, where)
                index, value = a["address"], a["value"]
            if type(index) is not int or not 0 <= index <= top:
                _port(index, top, where, f"write_output_{kind}_register")
            if kind == "boolean":
                if not isinstance(value, bool):
                    raise RunError(f"{where}: write_output_boolean_register takes True or False")
            else:
                value = num(value, where, "register value")
                value = int(value) if kind == "integer" else f32(value)
            fr.m.outputs[f"output_{kind}_register_{index}"] = value
            fr.m.output_written(where)

        def read_output(fr, args, kwargs, where):
            if len(args) == 1 and not kwargs:
                index = args[0]
            else:
                index = arguments(f"read_output_{kind}_register", ("address",), {}, args, kwargs, where)["address"]
            if type(index) is not int or not 0 <= index <= top:
                _port(index, top, where, f"read_output_{kind}_register")
            name = f"output_{kind}_register_{index}"  # what the program wrote, else what it held at the start
            value = fr.m.outputs.get(name, fr.m.inputs.get(name, 0))
            if kind == "boolean":
                return bool(value)
            return int(value) if kind == "integer" else f32(value)

        return read, write, read_output

    for kind in ("boolean", "integer", "float"):
        read, write, read_output = register(kind)
        table[f"read_input_{kind}_register"] = read
        table[f"write_output_{kind}_register"] = write
        table[f"read_output_{kind}_register"] = read_output

    def textmsg(fr, args, kwargs, where):
        if kwargs or not 1 <= len(args) <= 2:
            a = arguments("textmsg", ("s1", "s2"), {"s2": ""}, args, kwargs, where)
            args = (a["s1"], a["s2"])
        fr.m.message("".join(to_text(a) for a in args))

    def popup(fr, args, kwargs, where):
        # the operator's dialog; a blocking one waits for the operator, who confirms at once here
        a = arguments(
            "popup",
            ("s", "title", "warning", "error", "blocking"),
            {"title": "Popup", "warning": False, "error": False, "blocking": False},
            args,
            kwargs,
            where,
        )
        text = to_text(a["s"])
        if len(text) > STRING_MAX:
            raise RunError(f"{where}: popup text longer than {STRING_MAX} characters")
        fr.m.message(text)

    def sync(fr, args, kwargs, where):
        if args or kwargs:
            raise RunError(f"{where}: sync() takes no arguments")
        thread = threads.current(fr)
        if thread is not None:  # a thread: its slice ends here, the next one is the next cycle's
            thread.scheduler.pause(thread)
            return
        watching = fr.m.watching  # the main program: one controller cycle; devices act in between
        fr.m.elapse(STEP_TIME_S if watching is None else watching.cycle, where)

    def sleep(fr, args, kwargs, where):
        value = args[0] if len(args) == 1 and not kwargs else arguments("sleep", ("t",), {}, args, kwargs, where)["t"]
        seconds = float(num(value, where, "sleep time"))
        if not seconds >= 0 or not math.isfinite(seconds):
            raise RunError(f"{where}: sleep time must be a finite number of seconds >= 0, got {seconds}")
        thread = threads.current(fr)
        if thread is not None:  # a thread: no slices until then (physical time, like sync)
            thread.wake = fr.m.clock + seconds
            thread.scheduler.pause(thread)
            return
        fr.m.elapse(seconds, where)

    def get_steptime(fr, args, kwargs, where):
        arguments("get_steptime", (), {}, args, kwargs, where)
        return f32(STEP_TIME_S)

    return {
        **table,
        "set_standard_analog_out": set_standard_analog_out,
        "textmsg": textmsg,
        "popup": popup,
        "sync": sync,
        "sleep": sleep,
        "get_steptime": get_steptime,
    }
