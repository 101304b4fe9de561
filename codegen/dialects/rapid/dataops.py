"""RAPID instructions that change a variable: Incr, Decr, Add, Clear, the clocks (ClkStart...) and StrToVal."""

from __future__ import annotations

import re
from collections.abc import Callable

from lark import Tree

from codegen.dialects.core.source import Src
from codegen.dialects.core.values import Record, RunError, f32
from codegen.dialects.rapid.arguments import split_args
from codegen.dialects.rapid.types import num

# Sources: ABB, "Technical reference manual - RAPID Instructions, Functions and Data types" (RobotWare 6/7),
# Incr, Decr, Add, Clear, ClkReset, ClkStart, ClkStop, ClkRead, StrToVal, as recalled (the manual's text was
# not readable during this work):
# - Incr / Decr Name: a num (or dnum) variable or persistent plus / minus 1; Add Name, AddValue; Clear Name: 0;
# - a clock measures time: ClkReset sets it to 0 (stopped), ClkStart starts it, ClkStop stops it; ClkRead(Clock
#   [\HighRes]) the seconds it has run, in 0.001 s (\HighRes: 0.000001 s); here in the program's clock (moves take
#   their distance over their speed, waits their time);
# - StrToVal(Str, VAR Val): TRUE and Val set when Str is a literal of Val's type, FALSE and Val unchanged else.


def _variable(compiler, node, arg, what: str):
    if not (isinstance(arg, Tree) and arg.data in ("var", "index", "field")):
        compiler.fail(node, f"{node.children[0]}: {what} is a variable or persistent (it is written)")
    return compiler.expr(arg), compiler.lvalue(arg)


def _step(delta: float | None, takes_value: bool):
    def compile_(compiler, node, args_node) -> Callable:
        positional, _ = split_args(compiler, node, args_node, set())
        if len(positional) != (2 if takes_value else 1):
            compiler.fail(node, f"{node.children[0]} takes {'a variable and a value' if takes_value else 'a variable'}")
        read, store = _variable(compiler, node, positional[0], "the data")
        amount = compiler.expr(positional[1]) if takes_value else None
        where = compiler.where(node)

        def run(fr):
            old = read(fr)
            if delta is None and amount is None:  # Clear
                store(fr, 0.0 if type(old) is float else f32(0))
                return
            step = delta if amount is None else num(amount(fr), where)
            value = num(old, where) + step
            store(fr, value if type(old) is float else f32(value))

        return run

    return compile_


def _clock_variable(compiler, node, arg):
    read, store = _variable(compiler, node, arg, "the clock")
    where = compiler.where(node)

    def clock(fr) -> Record:
        value = read(fr)
        if not isinstance(value, Record) or value.type != "CLOCK":
            raise RunError(f"{where}: {node.children[0]}: expected a clock")
        return value

    return clock, store, where


def clock_zero() -> Record:
    return Record("CLOCK", {"RUNNING": False, "START": 0.0, "ELAPSED": 0.0})


def _elapsed(clock: Record, now: float) -> float:
    return clock["ELAPSED"] + (now - clock["START"] if clock["RUNNING"] else 0.0)


def _clock_instruction(action: str):
    def compile_(compiler, node, args_node) -> Callable:
        positional, _ = split_args(compiler, node, args_node, set())
        if len(positional) != 1:
            compiler.fail(node, f"{node.children[0]} takes one clock")
        clock, store, _where = _clock_variable(compiler, node, positional[0])

        def run(fr):
            c, now = clock(fr), fr.m.clock
            if action == "reset":
                store(fr, clock_zero())
            elif action == "start" and not c["RUNNING"]:
                store(fr, Record("CLOCK", {"RUNNING": True, "START": now, "ELAPSED": c["ELAPSED"]}))
            elif action == "stop" and c["RUNNING"]:
                store(fr, Record("CLOCK", {"RUNNING": False, "START": 0.0, "ELAPSED": _elapsed(c, now)}))

        return run

    return compile_


def clk_read(compiler, node, args_node) -> Src:
    positional, named = split_args(compiler, node, args_node, {"HIGHRES"})
    if len(positional) != 1:
        compiler.fail(node, "ClkRead takes one clock")
    clock, _store, _where = _clock_variable(compiler, node, positional[0])
    resolution = 1e6 if "HIGHRES" in named else 1e3

    def read(fr):
        return f32(round(_elapsed(clock(fr), fr.m.clock) * resolution) / resolution)

    return Src(f"{compiler.const(read)}(fr)")


_NUMBER = re.compile(r"\s*[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?\s*")


def parse_literal(text: str, kind, records: dict):
    """The value a literal of type kind spells (num, bool, string, a record or array aggregate), or None."""
    text = text.strip()
    if kind in ("NUM", "DNUM"):
        if not _NUMBER.fullmatch(text):
            return None
        return f32(float(text)) if kind == "NUM" else float(text)
    if kind == "BOOL":
        return {"TRUE": True, "FALSE": False}.get(text.upper())
    if kind == "STRING":
        return text[1:-1].replace('""', '"') if len(text) >= 2 and text[0] == text[-1] == '"' else None
    fields = records.get(kind) if isinstance(kind, str) else None
    if not (text.startswith("[") and text.endswith("]")):
        return None
    parts = _split(text[1:-1])
    if parts is None:
        return None
    if isinstance(kind, tuple):  # an array
        element, size = kind
        if size is not None and len(parts) != size:
            return None
        values = [parse_literal(p, element, records) for p in parts]
        return None if any(v is None for v in values) else values
    if fields is None or len(parts) != len(fields):
        return None
    values = [parse_literal(p, t, records) for p, (_k, t) in zip(parts, fields, strict=True)]
    if any(v is None for v in values):
        return None
    return Record(kind, {k: v for (k, _t), v in zip(fields, values, strict=True)})


def _split(text: str) -> list[str] | None:
    """An aggregate's items at its top-level commas."""
    parts, depth, quoted, start = [], 0, False, 0
    for i, c in enumerate(text):
        if c == '"':
            quoted = not quoted
        elif not quoted and c == "[":
            depth += 1
        elif not quoted and c == "]":
            depth -= 1
            if depth < 0:
                return None
        elif not quoted and c == "," and depth == 0:
            parts.append(text[start:i])
            start = i + 1
    parts.append(text[start:])
    return None if depth or quoted else parts


def str_to_val(compiler, node, args_node) -> Src:
    positional, _ = split_args(compiler, node, args_node, set())
    if len(positional) != 2:
        compiler.fail(node, "StrToVal takes a string and a variable")
    source = compiler.expr(positional[0])
    _read, store = _variable(compiler, node, positional[1], "the value")
    kind = compiler.static_type_of(positional[1])
    if kind is None:
        compiler.fail(node, "StrToVal: the variable's type is not known here")
    where = compiler.where(node)

    def run(fr):
        text = source(fr)
        if not isinstance(text, str):
            raise RunError(f"{where}: StrToVal needs a string")
        value = parse_literal(text, kind, compiler.records)
        if value is None:
            return False
        store(fr, value)
        return True

    return Src(f"{compiler.const(run)}(fr)")


SPECIAL = {
    "INCR": _step(1.0, False),
    "DECR": _step(-1.0, False),
    "ADD": _step(None, True),
    "CLEAR": _step(None, False),
    "CLKRESET": _clock_instruction("reset"),
    "CLKSTART": _clock_instruction("start"),
    "CLKSTOP": _clock_instruction("stop"),
}
FUNCTIONS = {"CLKREAD": clk_read, "STRTOVAL": str_to_val}
