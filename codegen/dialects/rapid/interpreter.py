"""RAPID interpreter: num in float32, trig in degrees, pose/robtarget records and Pose* functions."""

from __future__ import annotations

import math
import operator
import re

import numpy as np
from lark import Token, Tree

from codegen.dialects import posemath
from codegen.dialects.core.compiler import Compiler
from codegen.dialects.core.machine import MoveEvent, Program, halt
from codegen.dialects.core.parsing import parse_with_grammar
from codegen.dialects.core.source import Src
from codegen.dialects.core.values import F32, Record, RunError, constant, f32, format_fixed

QUATERNION_TOLERANCE = 1e-5  # assumed: RAPID rejects an unnormalised orientation in a move


def parse(text: str, filename: str = "<rapid>", positions: bool = True) -> Tree:
    return parse_with_grammar(__file__, text, filename, positions)


# Record types by field order (aggregates [a, b, ...] are positional).
RECORDS = {
    "POS": [("X", "NUM"), ("Y", "NUM"), ("Z", "NUM")],
    "ORIENT": [("Q1", "NUM"), ("Q2", "NUM"), ("Q3", "NUM"), ("Q4", "NUM")],
    "POSE": [("TRANS", "POS"), ("ROT", "ORIENT")],
    "CONFDATA": [("CF1", "NUM"), ("CF4", "NUM"), ("CF6", "NUM"), ("CFX", "NUM")],
    "EXTJOINT": [(f"EAX_{c}", "NUM") for c in "ABCDEF"],
    "ROBTARGET": [("TRANS", "POS"), ("ROT", "ORIENT"), ("ROBCONF", "CONFDATA"), ("EXTAX", "EXTJOINT")],
    "WOBJDATA": [("ROBHOLD", "BOOL"), ("UFPROG", "BOOL"), ("UFMEC", "STRING"), ("UFRAME", "POSE"), ("OFRAME", "POSE")],
}
SCALARS = {"NUM", "DNUM", "BOOL", "STRING"}
_PREDEFINED = re.compile(r"^(V\d+|VMAX|FINE|Z\d+|TOOL0|WOBJ0|LOAD0)$")


def _zero(type_name: str):
    if type_name in RECORDS:
        return Record(type_name, {k: _zero(t) for k, t in RECORDS[type_name]})
    return {"NUM": f32(0), "DNUM": 0.0, "BOOL": False, "STRING": ""}.get(type_name, f32(0))


_ZEROS = {name: _zero(name) for name in [*RECORDS, *SCALARS]}


def zero(type_name: str):
    """The value RAPID gives a declared variable without an initial value."""
    return _ZEROS.get(type_name, _ZEROS["NUM"])  # shared: values are never changed in place


def type_text(value) -> str:
    """A value's RAPID data type, for messages."""
    if isinstance(value, Record):
        return str(value.type).lower()
    if isinstance(value, bool):
        return "bool"
    if isinstance(value, str):
        return "string"
    if isinstance(value, list):
        return "array"
    if isinstance(value, int | float | np.number):
        return "num"
    return type(value).__name__


def _num(value, where: str) -> float:
    if type(value) is F32:  # the common case first
        return float(value)
    if isinstance(value, bool) or not isinstance(value, int | float | np.number):
        raise RunError(f"{where}: expected a num, got {type_text(value)}")
    return float(value)


def _rec(value, type_name: str, where: str) -> Record:
    if not isinstance(value, Record) or value.type != type_name:
        raise RunError(f"{where}: expected {type_name.lower()}, got {type_text(value)}")
    return value


def _vec(rec: Record, keys) -> list[float]:
    if keys == "XYZ":
        return list(map(float, _xyz(rec)))
    if keys == _QUAT_KEYS:
        return list(map(float, _quat(rec)))
    return [float(rec[k]) for k in keys]


_QUAT_KEYS = ("Q1", "Q2", "Q3", "Q4")
_xyz = operator.itemgetter("X", "Y", "Z")  # a pos record's numbers
_quat = operator.itemgetter(*_QUAT_KEYS)  # an orient record's numbers


def _pose_record(trans, quat) -> Record:
    x, y, z = trans
    q1, q2, q3, q4 = quat
    return Record(
        "POSE",
        {
            "TRANS": Record("POS", {"X": f32(x), "Y": f32(y), "Z": f32(z)}),
            "ROT": Record("ORIENT", {"Q1": f32(q1), "Q2": f32(q2), "Q3": f32(q3), "Q4": f32(q4)}),
        },
    )


class RAPIDCompiler(Compiler):
    name = "rapid"
    case_insensitive = True
    index_base = 1
    COERCE_UNCHANGED = {"NUM": "_F32", "BOOL": "bool"}
    RECORD_TYPES = frozenset(RECORDS)
    KWARGS_ERROR = "has no optional parameters"
    LIKE_UNCHANGED = frozenset({F32, bool})

    def __init__(self, filename: str) -> None:
        super().__init__(filename)
        self.data: list = []  # (key, type, dims, init closure)

    # --- tables ------------------------------------------------------------------------------
    def make_builtins(self) -> dict:
        def trig(fn):
            return lambda fr, a, k, w: f32(fn(math.radians(_num(a[0], w))))

        def atan2(fr, args, kwargs, where):
            return f32(math.degrees(math.atan2(_num(args[0], where), _num(args[1], where))))

        def sqrt(fr, args, kwargs, where):
            value = _num(args[0], where)
            if value < 0:
                raise RunError(f"{where}: Sqrt of a negative number")
            return f32(math.sqrt(value))

        def abs_(fr, args, kwargs, where):
            return f32(abs(_num(args[0], where)))

        def orient_zyx(fr, args, kwargs, where):
            z, y, x = (_num(a, where) for a in args)
            return Record(
                "ORIENT",
                dict(zip(("Q1", "Q2", "Q3", "Q4"), (f32(v) for v in posemath.quat_from_zyx_deg(z, y, x)), strict=True)),
            )

        def euler_zyx(fr, args, kwargs, where):
            axis = next((k for k in kwargs if k in ("X", "Y", "Z")), None)
            if axis is None or len(args) != 1:
                raise RunError(f"{where}: EulerZYX needs one of \\X, \\Y, \\Z and an orient")
            q = _vec(_rec(args[0], "ORIENT", where), ("Q1", "Q2", "Q3", "Q4"))
            m = posemath.quat_matrix((0, 0, 0), q)
            a, b, c = posemath.zyx_from(m)[3:]
            return f32({"Z": a, "Y": b, "X": c}[axis])

        def norient(fr, args, kwargs, where):
            q1, q2, q3, q4 = _vec(_rec(args[0], "ORIENT", where), ("Q1", "Q2", "Q3", "Q4"))
            n = math.sqrt(q1 * q1 + q2 * q2 + q3 * q3 + q4 * q4)
            if n == 0 or not math.isfinite(n):
                raise RunError(f"{where}: NOrient of a zero or non-finite orientation")
            return Record("ORIENT", {"Q1": f32(q1 / n), "Q2": f32(q2 / n), "Q3": f32(q3 / n), "Q4": f32(q4 / n)})

        def pose_parts(value, where):
            """Position and quaternion of a pose, or of an aggregate [pos, orient]."""
            if type(value) is list and len(value) == 2 and all(type(v) is Record for v in value):
                trans, rot = value
                if trans.type != "POS" or rot.type != "ORIENT":
                    trans, rot = self.coerce("POSE", value, where).values()
            else:
                trans, rot = self.coerce("POSE", value, where).values()
            return (
                [float(trans["X"]), float(trans["Y"]), float(trans["Z"])],
                [float(rot["Q1"]), float(rot["Q2"]), float(rot["Q3"]), float(rot["Q4"])],
            )

        def pose_mult(fr, args, kwargs, where):
            (t1, q1), (t2, q2) = (pose_parts(a, where) for a in args)
            rotated = posemath.quat_rotate(q1, t2)
            trans = [a + b for a, b in zip(t1, rotated, strict=True)]
            return _pose_record(trans, posemath.quat_multiply(q1, q2))

        def pose_inv(fr, args, kwargs, where):
            t, q = pose_parts(args[0], where)
            conj = (q[0], -q[1], -q[2], -q[3])
            trans = [-v for v in posemath.quat_rotate(conj, t)]
            return _pose_record(trans, conj)

        def pose_vect(fr, args, kwargs, where):
            t, q = pose_parts(args[0], where)
            p = _vec(self.coerce("POS", args[1], where), "XYZ")
            out = [a + b for a, b in zip(t, posemath.quat_rotate(q, p), strict=True)]
            return Record("POS", dict(zip("XYZ", (f32(v) for v in out), strict=True)))

        def num_to_str(fr, args, kwargs, where):
            return format_fixed(_num(args[0], where), int(_num(args[1], where)))

        def tpwrite(fr, args, kwargs, where):
            text = args[0]
            if not isinstance(text, str):
                raise RunError(f"{where}: TPWrite needs a string")
            if "NUM" in kwargs:
                text += _num_text(kwargs["NUM"])
            if len(text) > 80:
                raise RunError(f"{where}: TPWrite text longer than 80 characters")
            fr.m.trace.messages.append(text)

        def move(kind):
            def run(fr, args, kwargs, where):
                target = args[0]
                if type(target) is not Record or target.type != "ROBTARGET":
                    target = self.coerce("ROBTARGET", target, where)
                t = _vec(target["TRANS"], "XYZ")
                q = _vec(target["ROT"], _QUAT_KEYS)
                posemath.check_finite(t + q, where, "move target")
                q1, q2, q3, q4 = q
                norm = math.sqrt(q1 * q1 + q2 * q2 + q3 * q3 + q4 * q4)
                if abs(norm - 1.0) > QUATERNION_TOLERANCE:
                    raise RunError(f"{where}: orientation not normalised (|q| = {norm:.9f})")
                m = posemath.quat_matrix(t, q)
                wobj = kwargs.get("WOBJ")
                if isinstance(wobj, Record):  # base2tcp = uframe . oframe . target (wobj0: identity)
                    wobj = self.coerce("WOBJDATA", wobj, where)
                    if wobj["ROBHOLD"]:
                        raise RunError(f"{where}: a work object held by the robot is not supported")
                    frames = [wobj["UFRAME"], wobj["OFRAME"]]
                    for frame in reversed(frames):
                        m = (
                            posemath.quat_matrix(
                                _vec(frame["TRANS"], "XYZ"), _vec(frame["ROT"], ("Q1", "Q2", "Q3", "Q4"))
                            )
                            @ m
                        )
                elif wobj not in (None, "WOBJ0"):
                    raise RunError(f"{where}: unknown work object {wobj}")
                fr.m.trace.moves.append(MoveEvent(kind, m, int(where.split(":")[1])))

            return run

        return {
            "SIN": trig(math.sin),
            "COS": trig(math.cos),
            "TAN": trig(math.tan),
            "ATAN2": atan2,
            "SQRT": sqrt,
            "ABS": abs_,
            "ORIENTZYX": orient_zyx,
            "EULERZYX": euler_zyx,
            "NORIENT": norient,
            "POSEMULT": pose_mult,
            "POSEINV": pose_inv,
            "POSEVECT": pose_vect,
            "NUMTOSTR": num_to_str,
            "TPWRITE": tpwrite,
            "STOP": halt,
            "EXIT": halt,
            "MOVEJ": move("joint"),
            "MOVEL": move("linear"),
        }

    def number(self, text: str):
        return f32(float(text))

    def string_value(self, text: str) -> str:
        return text[1:-1].replace('""', '"').replace("\\\\", "\\")

    def coerce(self, type_name, value, where):
        if type_name is None:
            return value
        if type_name == "NUM":
            return value if type(value) is F32 else f32(_num(value, where))
        if isinstance(type_name, tuple):  # (element type, size) array
            element, size = type_name
            if not isinstance(value, list):
                raise RunError(f"{where}: expected an array of {element.lower()}")
            if size is not None and len(value) != size:
                raise RunError(f"{where}: expected {size} elements, got {len(value)}")
            if element == "NUM" and all(type(v) is F32 for v in value):
                return value
            return [self.coerce(element, v, where) for v in value]
        if type_name == "DNUM":
            return float(_num(value, where))
        if type_name == "BOOL":
            if not isinstance(value, bool):
                raise RunError(f"{where}: expected a bool")
            return value
        if type_name == "STRING":
            if not isinstance(value, str):
                raise RunError(f"{where}: expected a string")
            if len(value) > 80:
                raise RunError(f"{where}: string longer than 80 characters")
            return value
        if type_name in RECORDS:
            fields = RECORDS[type_name]
            if isinstance(value, Record):
                if value.type != type_name:
                    raise RunError(f"{where}: expected {type_name.lower()}, got {str(value.type).lower()}")
                return value
            if isinstance(value, list):
                if len(value) != len(fields):
                    raise RunError(f"{where}: {type_name.lower()} has {len(fields)} components, got {len(value)}")
                return Record(type_name, {k: self.coerce(t, v, where) for (k, t), v in zip(fields, value, strict=True)})
            raise RunError(f"{where}: expected {type_name.lower()}, got {type_text(value)}")
        return value  # speeddata, zonedata, tooldata...: opaque here

    def element_type(self, type_name):
        return type_name[0] if isinstance(type_name, tuple) else type_name

    # --- expressions -------------------------------------------------------------------------
    def var_reader(self, token):
        key = self.norm(str(token))
        where = self.where(token)
        predefined = key if _PREDEFINED.match(key) else None

        def read(fr):
            if key in fr.vars:
                return fr.vars[key]
            if key in fr.m.globals:
                return fr.m.globals[key]
            if predefined:
                return predefined
            raise RunError(f"{where}: undefined variable {token}")

        return read

    def e_intdiv(self, node):
        left, right = self.expr(node.children[0]), self.expr(node.children[2])
        return lambda fr: f32(int(float(left(fr)) / float(right(fr))))

    def e_mod(self, node):
        left, right = self.expr(node.children[0]), self.expr(node.children[2])
        return lambda fr: f32(math.fmod(float(left(fr)), float(right(fr))))

    def e_add(self, node):
        """num + num and string + string inline; pos records and errors through add()."""
        left, right = (self.src(c) for c in node.children)
        a, b = self.temp(), self.temp()
        return Src(
            f"({a} + {b} if (type({a} := {left}) is (_tb := type({b} := {right}))) & ((_tb is _F32) | (_tb is str)) "
            f"else {self.const(self.add)}({a}, {b}))"
        )

    def add(self, a, b):
        if isinstance(a, str) and isinstance(b, str):
            return a + b
        if isinstance(a, Record) and isinstance(b, Record) and a.type == b.type == "POS":
            return Record("POS", {k: f32(a[k] + b[k]) for k in "XYZ"})
        return a + b

    def e_aggregate(self, node):
        return Src("[" + ", ".join(self.src(c) for c in node.children) + "]")

    def e_index(self, node):
        base_node, *index_nodes = node.children
        if len(index_nodes) != 1:
            self.fail(node, "multi-dimensional arrays are not supported")
        return super().e_index(Tree("index", [base_node, index_nodes[0]], node.meta))

    def call_args(self, args_node):
        positional, named = [], {}
        for arg in args_node.children if args_node is not None else []:
            if isinstance(arg, Tree) and arg.data == "opt_arg":
                name, value = arg.children
                named[str(name).upper()] = self.src(value) if value is not None else "True"
            else:
                positional.append(arg)
        return positional, named

    def e_call(self, node):
        name, args_node = node.children
        positional, named = self.call_args(args_node)
        args = [self.src(a) for a in positional]
        setters = self.ref_setters(str(name), positional)
        return self.call_source(str(name), args, named, setters, self.where(node))

    def new_variable(self, fr, key, value, where):
        raise RunError(f"{where}: assignment to undeclared variable {key}")

    def coerce_like(self, old, value, where):
        if isinstance(old, Record):
            return self.coerce(old.type, value, where)
        if isinstance(old, bool):
            return self.coerce("BOOL", value, where)
        if isinstance(old, str):
            return self.coerce("STRING", value, where)
        return super().coerce_like(old, value, where)

    # --- statements --------------------------------------------------------------------------
    def s_proc_call(self, node):
        name, args_node = node.children
        if str(name).upper() == "WAITUNTIL":
            return self.rapid_wait_until(node, args_node)
        return self.s_call_stmt(node)

    def rapid_wait_until(self, node, args_node):
        positional, _named = self.call_args(args_node)
        if len(positional) != 1:
            self.fail(node, "WaitUntil takes one condition")
        return self.wait_until(positional[0], node, "WaitUntil")

    def s_compact_if(self, node):
        cond, statement = node.children
        return self.if_chain([(self.expr(cond), self.stmt(statement))], None, self.where(node))

    def body_block(self, body_node):
        for child in body_node.children:
            if isinstance(child, Tree) and child.data == "data_decl":
                self.fail(child, "declarations are only allowed at the start of a routine")
        return self.block(body_node.children)

    def s_for_stmt(self, node):
        """The counter is a local of the loop, set from the loop's own count at every pass."""
        name, start, stop, step, body = node.children
        key = str(name).upper()

        def store(fr, i):
            fr.vars[key] = f32(i)

        return self.for_loop(node, start, stop, step, body, number=float, store=store)

    def s_test_stmt(self, node):
        return self.switch(node, self.body_block)

    # --- declarations and routines -------------------------------------------------------------
    def decl(self, node):
        _local, _task, storage, type_name, name, dims, init = node.children
        key, type_key = str(name).upper(), str(type_name).upper()
        where = self.where(node)
        size_exprs = [self.expr(d) for d in dims.children] if dims is not None else []
        if len(size_exprs) > 1:
            self.fail(dims, "multi-dimensional arrays are not supported")
        value = self.expr(init) if init is not None else None
        if str(storage).upper() == "CONST" and value is None:
            self.fail(node, f"CONST {name} needs a value")

        def make(fr):
            if size_exprs:
                size = int(size_exprs[0](fr))
                full_type = (type_key, size)
                initial = value(fr) if value is not None else [zero(type_key) for _ in range(size)]
                return full_type, self.coerce(full_type, initial, where)
            return type_key, self.coerce(type_key, value(fr), where) if value is not None else zero(type_key)

        return key, make

    def static_type(self, node):
        """A declaration's type when it is known without running (array sizes as literals)."""
        _local, _task, _storage, type_name, _name, dims, _init = node.children
        type_key = str(type_name).upper()
        if dims is None:
            return type_key
        sizes = dims.children
        if len(sizes) == 1 and isinstance(sizes[0], Tree) and sizes[0].data == "number":
            return (type_key, int(float(str(sizes[0].children[0]))))
        return None

    def routine(self, node, returns: bool) -> None:
        children = [c for c in node.children if not (isinstance(c, Token) and c.type == "LOCAL") and c is not None]
        if returns:
            return_type, name, *rest = children
        else:
            name, *rest = children
            return_type = None
        params_node = rest[0] if len(rest) == 2 else None
        body = rest[-1]
        params = []
        for param in params_node.children if params_node is not None else []:
            optional, mode, ptype, pname, conformant = param.children
            if optional is not None:
                self.fail(param, "optional parameters of user routines are not supported")
            type_key = str(ptype).upper()
            full_type = (type_key, None) if conformant is not None else type_key
            params.append((str(pname).upper(), str(mode).upper() if mode else "IN", full_type))
        decls = []  # (name, static type, initialiser)

        def declare(child):
            key, make = self.decl(child)
            static_type = self.static_type(child)
            decls.append((key, static_type, self._local_init(child, static_type, make)))

        message = "declarations are only allowed at the start of a routine"
        statements = self.routine_statements(body, "data_decl", declare, message)
        local_types = {p: t for p, _m, t in params} | {k: t for k, t, _init in decls}
        return_type = str(return_type).upper() if return_type else None
        self.define_routine(str(name).upper(), name, params, return_type, node, statements, decls, local_types)

    def _local_init(self, node, static_type, make):
        """A local's initialiser: its zero value shared by every call when it has no initial
        value and a known size (values are never changed in place)."""
        if node.children[-1] is None and static_type is not None:
            if isinstance(static_type, tuple):
                return constant([zero(static_type[0])] * static_type[1])
            return constant(zero(static_type))
        return lambda fr: make(fr)[1]


def load(text: str, filename: str = "<rapid>") -> Program:
    tree = parse(text, filename)
    compiler = RAPIDCompiler(filename)
    module = tree.children[0]
    compiler.user_routines = set()
    for item in module.children:
        if isinstance(item, Tree) and item.data in ("proc", "func"):
            named = [c for c in item.children if c is not None and not (isinstance(c, Token) and c.type == "LOCAL")]
            compiler.user_routines.add(str(named[0 if item.data == "proc" else 1]).upper())
    data = []
    for item in module.children:
        if not isinstance(item, Tree):
            continue
        if item.data == "data_decl":
            data.append(compiler.decl(item))
        elif item.data == "proc":
            compiler.routine(item, returns=False)
        elif item.data == "func":
            compiler.routine(item, returns=True)
        elif item.data == "trap":
            continue
    if "MAIN" not in compiler.routines:
        raise RunError(f"{filename}: no PROC main")

    def init(fr):
        for key, make in data:
            type_name, value = make(fr)
            fr.m.global_types[key] = type_name
            fr.m.globals[key] = value

    return Program(str(module.children[0]), compiler, init, "MAIN")


def _num_text(value) -> str:
    """TPWrite \\Num: integers without decimals, else up to 6 significant digits (as the FlexPendant)."""
    v = float(value)
    if v == int(v) and abs(v) < 1e9:
        return str(int(v))
    return f"{v:.6g}"
