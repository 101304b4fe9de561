"""Decompose/Trans interpreter: Double in float32 (assumed), trig in degrees, Point = [x y z rx ry rz]."""

from __future__ import annotations

import math
import re

import numpy as np
from lark import Tree

from codegen.dialects import posemath
from codegen.dialects.core.compiler import Compiler
from codegen.dialects.core.limits import array_size_problem
from codegen.dialects.core.machine import MoveEvent
from codegen.dialects.core.parsing import parse_with_grammar
from codegen.dialects.core.program import Program
from codegen.dialects.core.source import Inline
from codegen.dialects.core.values import F32, Record, RunError, f32, format_fixed, format_general

POINT_KEYS = ("x", "y", "z", "rx", "ry", "rz")
FORMAT_FIELD = re.compile(r"%(-?\d*)(?:\.(\d+))?([dfsg%])")  # a TPWrite format's field: width, decimals, kind


def parse(text: str, filename: str = "<dtrans>", positions: bool = True) -> Tree:
    return parse_with_grammar(__file__, text, filename, positions)


def point(values) -> Record:
    return Record("Point", dict(zip(POINT_KEYS, (f32(v) for v in values), strict=True)))


def _num(value, where):
    if type(value) is F32:  # the common case first
        return float(value)
    if isinstance(value, bool) or not isinstance(value, int | float | np.number):
        raise RunError(f"{where}: expected a number, got {type(value).__name__}")
    return float(value)


MESSAGE_MAX = 80  # characters of a TPWrite message (assumed as RAPID's: targets/dtrans.toml string_max)


def printf(fmt: str, args: list, where: str) -> str:
    values = iter(args)

    def one(match):
        width, decimals, kind = match.groups()
        if kind == "%":
            return "%"
        if (decimals and int(decimals) > MESSAGE_MAX) or (width and abs(int(width)) > MESSAGE_MAX):
            field = match.group(0)
            raise RunError(f"{where}: format field {field!r} is wider than a message ({MESSAGE_MAX} characters)")
        try:
            value = next(values)
        except StopIteration:
            raise RunError(f"{where}: format {fmt!r} needs more arguments") from None
        if kind == "d":
            text = str(int(_num(value, where)))
        elif kind == "f":
            text = format_fixed(_num(value, where), int(decimals) if decimals else 6)
        elif kind == "g":
            text = format_general(value)
        else:
            text = str(value)
        return text.rjust(int(width)) if width and not width.startswith("-") else text

    text = FORMAT_FIELD.sub(one, fmt)
    if next(values, None) is not None:
        raise RunError(f"{where}: format {fmt!r} has fewer fields than arguments")
    return text


IO_MAX = 15  # digital I/O 0..15 (assumed, dtrans.toml signals)


def _io_index(value, where: str) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value <= IO_MAX:
        raise RunError(f"{where}: a digital signal number is 0..{IO_MAX}, got {value!r}")
    return value


def _trig(fn):
    return lambda fr, a, k, w: f32(fn(math.radians(_num(a[0], w))))


def trans(fr, args, kwargs, where):
    if len(args) != 6:
        raise RunError(f"{where}: Trans takes 6 numbers, got {len(args)}")
    # a float32 argument is its own float32 value: kept, not converted there and back
    values = [a if type(a) is F32 else f32(_num(a, where)) for a in args]
    return Record("Point", dict(zip(POINT_KEYS, values, strict=True)))


def din(fr, args, kwargs, where):
    return fr.m.input_signal(f"DI[{_io_index(args[0], where)}]", False)  # a live device's value first


def sqrt(fr, args, kwargs, where):
    value = _num(args[0], where)
    if value < 0:
        raise RunError(f"{where}: sqrt of a negative number")
    return f32(math.sqrt(value))


BUILTINS = {  # the functions the interpreter provides, by name
    "sin": _trig(math.sin),
    "cos": _trig(math.cos),
    "tan": _trig(math.tan),
    "atan2": lambda fr, a, k, w: f32(math.degrees(math.atan2(_num(a[0], w), _num(a[1], w)))),
    "sqrt": sqrt,
    "abs": lambda fr, a, k, w: abs(a[0]) if isinstance(a[0], int) else f32(abs(_num(a[0], w))),
    "Trans": trans,
    "DIn": din,
}


class DTransCompiler(Compiler):
    name = "dtrans"
    index_base = 0
    COERCE_UNCHANGED = {"Double": "_F32", "Int": "int", "Bool": "bool"}
    RECORD_TYPES = frozenset({"Point"})
    LIKE_UNCHANGED = frozenset({F32, int})

    def make_builtins(self) -> dict:
        return dict(BUILTINS)

    def coerce(self, type_name, value, where):
        if type_name is None:
            return value
        if isinstance(type_name, tuple):
            return self.coerce_array(type_name, value, where, type_name[0])
        if type_name == "Double":
            return value if type(value) is F32 else f32(_num(value, where))
        if type_name == "Int":
            v = _num(value, where)
            if not math.isfinite(v):
                raise RunError(f"{where}: cannot store a non-finite value in an Int")
            return int(v)
        if type_name == "Point":
            if not isinstance(value, Record) or value.type != "Point":
                raise RunError(f"{where}: expected a Point")
            return value
        if type_name == "Bool":
            if not isinstance(value, bool):
                raise RunError(f"{where}: expected a Bool")
            return value
        if type_name == "String":
            if not isinstance(value, str):
                raise RunError(f"{where}: expected a String")
            return value
        return value

    def element_type(self, type_name):
        return type_name[0] if isinstance(type_name, tuple) else type_name

    def e_array_lit(self, node):
        parts = [self.expr(c) for c in node.children]
        return lambda fr: [p(fr) for p in parts]

    def e_call(self, node):
        name, args_node = node.children
        args = [self.src(a) for a in (args_node.children if args_node is not None else [])]
        return self.call_source(str(name), args, {}, None, self.where(node))

    def new_variable(self, fr, key, value, where):
        raise RunError(f"{where}: assignment to undeclared variable {key}")

    def coerce_like(self, old, value, where):
        if isinstance(old, int) and not isinstance(old, bool):
            return self.coerce("Int", value, where)
        if isinstance(old, Record):
            return self.coerce("Point", value, where)
        return super().coerce_like(old, value, where)

    # --- statements --------------------------------------------------------------------------
    DEFAULTS = {"Double": f32(0), "Int": 0, "Bool": False, "String": "", "Point": point([0] * 6)}

    def s_decl(self, node):
        """Type name[size] [= value]: without a value, one shared default (values are never
        changed in place)."""
        type_token, name, size, init = node.children
        type_name = str(type_token)
        full_type = (type_name, int(str(size))) if size is not None else type_name
        if size is not None and (problem := array_size_problem([full_type[1]])):
            self.fail(node, problem)
        key, where = repr(str(name)), self.where(node)
        lines = [f"fr.types[{key}] = {self.const(full_type)}"]
        if init is None:
            default = self.DEFAULTS[type_name]
            value = [default] * full_type[1] if isinstance(full_type, tuple) else default
            return Inline(self, [*lines, f"V[{key}] = {self.const(value)}"])
        lines += [f"_v = {self.src(init)}", f"V[{key}] = {self.coerce_source(full_type, '_v', repr(where))}"]
        return Inline(self, self.guarded(lines, where))

    def s_decompose(self, node):
        target, value_node = node.children
        if not (isinstance(target, Tree) and target.data == "index"):
            self.fail(node, "Decompose writes into an array element: Decompose arr[i] = point")
        array, start = self.expr(target.children[0]), self.expr(target.children[1])
        store = self.lvalue(target.children[0])
        value = self.expr(value_node)
        where = self.where(node)

        def run(fr):
            seq, i, pt = array(fr), int(start(fr)), value(fr)
            if not isinstance(pt, Record) or pt.type != "Point":
                raise RunError(f"{where}: Decompose needs a Point")
            if not isinstance(seq, list) or i < 0 or i + 6 > len(seq):
                raise RunError(f"{where}: Decompose needs 6 elements from index {i}")
            changed = list(seq)
            for k, key in enumerate(POINT_KEYS):
                old, new = seq[i + k], pt[key]
                changed[i + k] = new if type(new) is type(old) is F32 else self.coerce_like(old, new, where)
            store(fr, changed)

        return run

    def s_wait_stmt(self, node):
        return self.wait_until(node.children[0], node, "WaitUntil")

    def s_setdo_stmt(self, node):
        index, value, where = self.expr(node.children[0]), self.expr(node.children[1]), self.where(node)

        def run(fr):
            on = value(fr)
            if not isinstance(on, bool):
                raise RunError(f"{where}: SetDO takes True or False")
            fr.m.set_output(f"DO[{_io_index(index(fr), where)}]", on, where)  # moves block: the arm stands still

        return run

    def s_sleep_stmt(self, node):
        seconds, where = self.expr(node.children[0]), self.where(node)

        def run(fr):
            value = seconds(fr)
            if isinstance(value, (bool, str, list, Record)) or not math.isfinite(float(value)):
                raise RunError(f"{where}: Sleep takes a finite number of seconds")
            fr.m.elapse(float(value), where)

        return run

    def s_motion_stmt(self, node):
        motion, target = node.children
        kind = "joint" if str(motion) == "MovJ" else "linear"
        value = self.expr(target)
        where, line = self.where(node), self.line(node)

        def run(fr):
            pt = value(fr)
            if not isinstance(pt, Record) or pt.type != "Point":
                raise RunError(f"{where}: {motion} needs a Point")
            values = [pt[k] for k in POINT_KEYS]
            posemath.check_finite(values, where, "motion target")
            x, y, z, rx, ry, rz = values
            # a move returns when the arm has arrived (assumed); the dialect has no speed: it takes no time
            fr.m.move(MoveEvent(kind, posemath.matrix_from_xyzabc((x, y, z, rz, ry, rx)), line))

        return run

    def s_tpwrite_stmt(self, node):
        channel, fmt, *args = (self.expr(c) for c in node.children)
        where = self.where(node)

        def run(fr):
            text = fmt(fr)
            if not isinstance(text, str):
                raise RunError(f"{where}: TPWrite needs a format string")
            channel(fr)
            fr.m.message(printf(text, [a(fr) for a in args], where))

        return run

    def routine(self, node, returns: bool) -> None:
        type_token, name, param_parts, body = self.routine_parts(node.children, returns)
        params = [
            (str(pname), "IN", (str(ptype), None) if brackets is not None else str(ptype))
            for ptype, pname, brackets in param_parts
        ]
        return_type = str(type_token) if type_token else None
        self.define_routine(str(name), name, params, return_type, node, body.children)


def load(text: str, filename: str = "<dtrans>") -> Program:
    return load_tree(parse(text, filename), filename)


def load_tree(tree: Tree, filename: str) -> Program:
    """The program of a parsed file (parse with positions)."""
    compiler = DTransCompiler(filename)
    data, main = [], []
    for item in tree.children:
        if not isinstance(item, Tree):
            continue
        if item.data == "function":
            compiler.routine(item, returns=True)
        elif item.data == "sub":
            compiler.routine(item, returns=False)
        elif item.data == "decl" and not main:
            data.append(compiler.stmt(item))
        else:
            main.append(item)
    body = compiler.block(main)

    def init(fr):
        for statement in data:
            statement(fr)

    return Program(filename, compiler, init, None, body)
