"""KRL interpreter: REAL in float32, trig in degrees, FRAME/POS with the geometric operator `:`."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from lark import Token, Tree

from codegen.dialects import posemath
from codegen.dialects.core.compiler import Compiler
from codegen.dialects.core.machine import Program, pause
from codegen.dialects.core.parsing import parse_with_grammar
from codegen.dialects.core.source import Src
from codegen.dialects.core.values import F32, Record, RunError, Signal, constant, f32
from codegen.dialects.krl import io
from codegen.dialects.krl.builtins import (
    CART,
    SIMPLE,
    STRUCT_FIELDS,
    STRUCTS,
    UNINIT,
    builtins,
    cart,
    cart_matrix,
    frame,
    new_value,
    valid,
    xyzabc,
)
from codegen.dialects.krl.interrupts import InterruptStatements, pos_int, routine_signatures
from codegen.dialects.krl.motion import (
    ACTIVE_BASE_AT_START,
    SYSTEM_ARRAY,
    SYSTEM_ARRAYS,
    CircStatement,
    motion_run,
    orientation_store,
    path_variable_store,
    robroot,
    system_inputs,
)
from codegen.dialects.krl.signals import SignalGroups


def parse(text: str, filename: str = "<krl>", positions: bool = True) -> Tree:
    return parse_with_grammar(__file__, text, filename, positions)


EXIT = frozenset({"exit"})  # the signal kind that ends a KRL loop
NO_SKIP = frozenset()


class KRLCompiler(SignalGroups, InterruptStatements, CircStatement, io.ContinueStatement, Compiler):
    name = "krl"
    case_insensitive = True
    index_base = 1
    int_division = True
    halt_resumes = True  # HALT stops the program; the operator's start resumes it at the next statement
    COERCE_UNCHANGED = {"REAL": "_F32", "INT": "int", "BOOL": "bool"}
    INT_RANGE = (-(2**31), 2**31 - 1)  # INT is 32-bit (KRL quick guide, data types): overflow is an error
    LIKE_UNCHANGED = frozenset({F32, int, bool, str})
    RECORD_TYPES = frozenset(STRUCTS)

    def __init__(self, filename: str) -> None:
        super().__init__(filename)
        self.data_decls: list = []
        self.ns.update(_UNINIT=UNINIT, _valid=valid)

    # --- tables ------------------------------------------------------------------------------
    def make_builtins(self) -> dict:
        return builtins()

    def number(self, text: str):
        if any(c in text for c in ".eE"):
            return f32(float(text))
        return int(text)

    def coerce(self, type_name, value, where):
        if type_name is None:
            return value
        if isinstance(type_name, tuple):  # array type (element type, size)
            return value
        if value is UNINIT:
            return value
        if type_name == "REAL":
            if type(value) is F32:
                return value
            if isinstance(value, bool) or not isinstance(value, int | float | np.number):
                raise RunError(f"{where}: cannot assign {getattr(value, 'type', type(value).__name__)} to REAL")
            return f32(value)
        if type_name == "INT":
            if isinstance(value, bool) or not isinstance(value, int | float | np.number):
                raise RunError(f"{where}: cannot assign {type(value).__name__} to INT")
            if not math.isfinite(float(value)):
                raise RunError(f"{where}: cannot assign a non-finite value to INT")
            rounded = math.floor(float(value) + 0.5) if not isinstance(value, int) else value
            low, high = self.INT_RANGE
            if not low <= rounded <= high:
                raise RunError(f"{where}: value {value:.6g} out of the INT range {low}..{high} (32-bit)")
            return rounded
        if type_name == "BOOL":
            if not isinstance(value, bool):
                raise RunError(f"{where}: cannot assign {type(value).__name__} to BOOL")
            return value
        if type_name in ("CHAR", "ENUM"):
            return value
        if type_name in STRUCTS:
            if not isinstance(value, Record):
                raise RunError(f"{where}: cannot assign {type(value).__name__} to {type_name}")
            if value.type == type_name:
                return value
            fields = STRUCT_FIELDS[type_name]
            if value.type is None or (value.type in CART and type_name in CART):
                out = new_value(type_name)
                for key, v in value.items():
                    if key in fields:
                        out[key] = self.coerce(fields[key], v, where)
                    elif value.type is None:
                        raise RunError(f"{where}: {type_name} has no component {key}")
                return out
            raise RunError(f"{where}: cannot assign {value.type} to {type_name}")
        raise RunError(f"{where}: unknown type {type_name}")

    def element_type(self, type_name):
        return type_name[0] if isinstance(type_name, tuple) else type_name

    def accepts_input(self, name: str, globals_: dict) -> bool:
        match = SYSTEM_ARRAY.fullmatch(name.upper())
        if match is not None:
            return 1 <= int(match.group(2)) <= SYSTEM_ARRAYS[match.group(1)][1]
        return name.upper() == "$ROBROOT" or super().accepts_input(name, globals_)

    def inject_inputs(self, machine) -> None:
        """BASE_DATA[n]=x,y,z,a,b,c, TOOL_DATA[n]=x,y,z,a,b,c and LOAD_DATA[n]=m,x,y,z (mass kg, centre of
        gravity mm) set the controller's numbered bases, tools and loads, as $config.dat holds them."""
        robroot(machine)
        rest = system_inputs(machine)
        if rest is None:
            return super().inject_inputs(machine)
        original, machine.inputs = machine.inputs, rest
        try:
            super().inject_inputs(machine)
        finally:
            machine.inputs = original

    # --- expressions -------------------------------------------------------------------------
    def var_reader(self, token):
        key = self.norm(name := str(token))  # the reader keeps the name: a kept token keeps the parse tree's memory
        where = self.where(token)
        if key == "$NULLFRAME":
            return lambda fr: frame()

        def read(fr):
            if key in fr.vars:
                value = fr.vars[key]
            elif key in fr.m.globals:
                value = fr.m.globals[key]
            elif key == "$BASE":
                return fr.m.extra.setdefault("$BASE", frame(ACTIVE_BASE_AT_START))
            elif key == "$ROBROOT":  # the robot's base in the world (KSS 8 system variables; read-only)
                return fr.m.extra.get("$ROBROOT") or frame()
            elif key == "$POS_INT":  # where the arm was when an interrupt fired (codegen/dialects/krl/interrupts.py)
                return pos_int(fr.m, where)
            elif key in ("$ORI_TYPE", "$CIRC_TYPE"):
                if key not in fr.m.extra:
                    raise RunError(f"{where}: {key} has no value here (the program sets it: no default is assumed)")
                return fr.m.extra[key]
            elif key in SYSTEM_ARRAYS:  # the controller's numbered bases, tools and loads ($config.dat)
                type_name, size, _shape = SYSTEM_ARRAYS[key]
                return fr.m.extra.setdefault(key, [new_value(type_name) for _ in range(size)])
            else:
                raise RunError(f"{where}: undefined variable {name}")
            return valid(value, where, name)

        return read

    def e_enum(self, node):
        return Src(repr("#" + str(node.children[0]).upper()))

    def e_whole(self, node):
        return self.expr(node.children[0])

    def var_source(self, token) -> Src:
        """Declared and initialised variables inline; the rest (UNINIT, $BASE...) via var_reader."""
        key = repr(self.norm(str(token)))
        if key == repr("$NULLFRAME"):
            return Src(f"{self.const(self.var_reader(token))}(fr)")
        fallback = self.const(self.var_reader(token))
        if self.local_types is not None and self.norm(str(token)) in self.local_types:
            return Src(f"(V[{key}] if V[{key}] is not _UNINIT else {fallback}(fr))")
        if self.local_types is not None:  # not a local: KRL declares every local (no implicit ones)
            return Src(f"(G[{key}] if G.get({key}, _UNINIT) is not _UNINIT else {fallback}(fr))")
        return Src(
            f"(V[{key}] if V.get({key}, _UNINIT) is not _UNINIT "
            f"else G[{key}] if {key} not in V and G.get({key}, _UNINIT) is not _UNINIT else {fallback}(fr))"
        )

    def e_field(self, node):
        inner = super().e_field(node)
        where, name = self.where(node), str(node.children[1])
        return Src(f"(_u if (_u := {inner}) is not _UNINIT else _valid(_u, {where!r}, {name!r}))")

    def e_index(self, node):
        io_read = io.input_read(self, node)
        if io_read is not None:
            return io_read
        base_node, *index_nodes = node.children
        if len(index_nodes) != 1:
            self.fail(node, "multi-dimensional arrays are not supported")
        inner = super().e_index(Tree("index", [base_node, index_nodes[0]], node.meta))
        return Src(f"_valid({inner}, {self.where(node)!r}, 'array element')")

    def e_geo(self, node):
        left, right = (self.expr(c) for c in node.children)
        where = self.where(node)

        def geo(fr):
            a, b = cart(left(fr), where), cart(right(fr), where)
            out = b.shallow()  # result has the type, status and turn of the right operand
            x, y, z, a_, b_, c = posemath.xyzabc_concat(xyzabc(a), xyzabc(b))
            out.update(X=f32(x), Y=f32(y), Z=f32(z), A=f32(a_), B=f32(b_), C=f32(c))
            return out

        return geo

    def e_aggregate(self, node):
        children = [c for c in node.children if c is not None]
        type_name = None
        if children and isinstance(children[0], Token):
            type_name = str(children[0]).upper()
            children = children[1:]
        fields = []
        for item in children:
            name, _brackets, value = item.children
            fields.append(f"{str(name).upper()!r}: {self.src(value)}")
        record = f"_Record(None, {{{', '.join(fields)}}})"
        if type_name is None:
            return Src(record)
        return Src(f"{self.const(self.coerce)}({type_name!r}, {record}, {self.where(node)!r})")

    def e_call(self, node):
        name, args_node = node.children
        arg_nodes = args_node.children if args_node is not None else []
        args = [self.src(a) for a in arg_nodes]
        setters = self.ref_setters(str(name), arg_nodes)
        return self.call_source(str(name), args, {}, setters, self.where(node))

    # --- lvalues and assignment --------------------------------------------------------------
    def coerce_source(self, type_name, value: str, where: str) -> str:
        if isinstance(type_name, tuple):  # an array keeps its elements' own checks (coerce_like)
            return value
        return super().coerce_source(type_name, value, where)

    def coerce_like_source(self, old: str, value: str, where: str) -> str:
        """A component without a value takes the new one as it is (see coerce_like)."""
        return f"({value} if {old} is _UNINIT else {super().coerce_like_source(old, value, where)})"

    def assign_target(self, node):
        while isinstance(node, Tree) and node.data == "whole":
            node = node.children[0]
        return node

    def coerce_like(self, old, value, where):
        if isinstance(old, Record) and isinstance(value, Record) and value.type is None:
            out = old.shallow()  # a partial aggregate changes only the components it names
            fields = STRUCT_FIELDS.get(old.type, {})
            for key, v in value.items():
                if key not in out:
                    raise RunError(f"{where}: {old.type} has no component {key}")
                out[key] = self.coerce(fields.get(key), v, where)
            return out
        if isinstance(old, Record) and isinstance(value, Record):
            return self.coerce(old.type, value, where)
        if old is UNINIT:
            return value
        if isinstance(old, bool):
            return self.coerce("BOOL", value, where)
        if isinstance(old, int):
            return self.coerce("INT", value, where)
        return super().coerce_like(old, value, where)

    def new_variable(self, fr, key, value, where):
        if key == "$BASE":
            fr.m.extra["$BASE"] = self.coerce("FRAME", value, where)
            return
        if key in SYSTEM_ARRAYS and key in fr.m.extra:  # an element was assigned
            fr.m.extra[key] = value
            return
        raise RunError(f"{where}: assignment to undeclared variable {key}")

    def s_assign(self, node):
        target_node, value_node = node.children
        is_var = isinstance(target_node, Tree) and target_node.data == "var"
        system_store = (
            path_variable_store(self, target_node, value_node, node)
            or orientation_store(self, target_node, value_node, node)
            or io.output_store(self, target_node, value_node, node)
        )
        if system_store is not None:
            return system_store
        if is_var and str(target_node.children[0]).upper() == "$BASE":
            value, where = self.expr(value_node), self.where(node)

            def set_base(fr):
                fr.m.extra["$BASE"] = self.coerce("FRAME", value(fr), where)

            return set_base
        if is_var and str(target_node.children[0]).upper() == "$TOOL":
            value, where = self.expr(value_node), self.where(node)

            def set_tool(fr):
                tool = cart(self.coerce("FRAME", value(fr), where), where)
                posemath.check_finite(xyzabc(tool), where, "$TOOL")
                fr.m.extra["$TOOL"] = tool
                fr.m.arm.tcp2flange = cart_matrix(tool)

            return set_tool
        if is_var and str(target_node.children[0]).upper() == "$LOAD":
            value, where = self.expr(value_node), self.where(node)

            def set_load(fr):
                fr.m.extra["$LOAD"] = self.coerce("LOAD", value(fr), where)

            return set_load
        return super().s_assign(node)

    # --- declarations ------------------------------------------------------------------------
    def decl_items(self, node):
        """[(name, type, init closure)] for one DECL line."""
        children = [c for c in node.children if c is not None]
        tokens = [c for c in children if isinstance(c, Token)]
        type_token = next(t for t in tokens if t.type == "NAME")
        type_name = str(type_token).upper()
        if type_name not in SIMPLE and type_name not in STRUCTS:
            self.fail(type_token, f"unknown type {type_token}")
        out = []
        for item in (c for c in children if isinstance(c, Tree) and c.data == "decl_item"):
            name, dims, init = item.children
            key = str(name).upper()
            where = self.where(item)
            if dims is not None:
                sizes = [int(str(t)) for t in dims.children]
                if len(sizes) != 1:
                    self.fail(dims, "multi-dimensional arrays are not supported")
                size = sizes[0]
                if type_name == "CHAR":
                    value_init = self.expr(init) if init is not None else None
                    out.append((key, "CHAR", (lambda fr, v=value_init: v(fr) if v else UNINIT)))
                else:
                    # one shared initial array: values are never changed in place
                    initial = [new_value(type_name) for _ in range(size)]
                    out.append((key, (type_name, size), constant(initial)))
                continue
            if init is None:
                out.append((key, type_name, constant(new_value(type_name))))
            else:
                value = self.expr(init)
                out.append((key, type_name, (lambda fr, t=type_name, v=value, w=where: self.coerce(t, v(fr), w))))
        return out

    def s_decl(self, node):
        self.fail(node, "DECL after the first statement of a routine (KRL: declarations come first)")

    # --- statements --------------------------------------------------------------------------
    # EXIT leaves LOOP, REPEAT and FOR (from WHILE it is passed on as before).
    def s_loop_stmt(self, node):
        return self.loop(self.where(node), self.body_block(node.children[0]), leave=EXIT, skip=NO_SKIP)

    def s_repeat_stmt(self, node):
        body_node, until_node = node.children
        body, until = self.body_block(body_node), self.expr(until_node)
        return self.loop(self.where(node), body, until=until, leave=EXIT, skip=NO_SKIP)

    def s_for_stmt(self, node):
        name, start, stop, step, body = node.children
        store, read = self.lvalue(Tree("var", [name], node.meta)), self.var_reader(name)
        return self.for_loop(node, start, stop, step, body, number=int, store=store, read=read, leave=EXIT)

    def s_switch_stmt(self, node):
        return self.switch(node, self.body_block)

    def s_exit_stmt(self, node):
        return lambda fr: Signal("exit")

    def s_wait_sec(self, node):
        # WAIT SEC stops the advance run: the time runs from the arm's arrival (KSS 8 programming manual)
        seconds, where = self.expr(node.children[0]), self.where(node)

        def run(fr):
            t = float(valid(seconds(fr), where, "WAIT SEC time"))
            fr.m.arrive(where)
            fr.m.elapse(t, where)

        return run

    def s_wait_for(self, node):
        return self.wait_until(node.children[0], node, "WAIT FOR", arrive=True)  # stops the advance run

    def s_halt_stmt(self, node):
        where = self.where(node)

        def run(fr):  # HALT stops the advance run: the arm stops at the end of its move
            fr.m.arrive(where)
            pause(fr)

        return run

    def s_motion_stmt(self, node):
        motion, target, approx = node.children
        static = {"approx": str(approx).upper() if approx is not None else None}
        kind = {"PTP": "joint", "LIN": "linear"}.get(str(motion).upper())
        if kind is None:
            self.fail(node, f"{motion} is not supported by this interpreter")
        value = self.expr(target)
        where = self.where(node)
        line = self.line(node)

        return motion_run(self, kind, static, value, where, line)

    # --- routines ----------------------------------------------------------------------------
    def routine(self, node, returns: bool) -> None:
        type_token, name, param_parts, body = self.routine_parts(node.children, returns)
        params = [
            (str(pname).upper(), str(mode).upper() if mode is not None else "IN", None)
            for pname, _brackets, mode in param_parts
        ]
        decls = []
        message = "DECL after the first statement of a routine (KRL: declarations come first)"
        statements = self.routine_statements(body, "decl", lambda child: decls.extend(self.decl_items(child)), message)
        # parameters are typed by their DECL lines
        declared = {d[0]: d[1] for d in decls}
        params = [(p, m, declared.get(p)) for p, m, _ in params]
        local_decls = [d for d in decls if d[0] not in {p for p, _, _ in params}]
        return_type = str(type_token).upper() if type_token else None
        self.define_routine(str(name).upper(), name, params, return_type, node, statements, local_decls, declared)

    def check_params(self, node, name, params) -> None:
        for pname, _m, ptype in params:
            if ptype is None:
                self.fail(node, f"parameter {pname} of {name} has no DECL")

    def data_list(self, node) -> None:
        for child in node.children[-1].children:
            if not isinstance(child, Tree):
                continue
            if child.data == "decl":
                self.data_decls.append(("decl", self.decl_items(child)))
            elif child.data == "signal_decl":
                self.s_signal_decl(child)
            else:
                self.data_decls.append(("assign", self.s_assign(child)))

    def init_data(self, fr) -> None:
        for kind, payload in self.data_decls:
            if kind == "decl":
                for key, type_name, init in payload:
                    fr.m.global_types[key] = type_name
                    fr.m.globals[key] = init(fr)
            else:
                payload(fr)


def load(text: str, filename: str = "<krl>", dat_text: str | None = None) -> Program:
    """A .src (with its .dat beside it when given) compiled into a runnable program."""
    compiler = KRLCompiler(filename)
    if dat_text is not None:
        dat_name = str(Path(filename).with_suffix(".dat"))
        dat_compiler_filename = compiler.filename
        compiler.filename = dat_name
        for item in parse(dat_text, dat_name).children:
            if isinstance(item, Tree) and item.data == "defdat":
                compiler.data_list(item)
        compiler.filename = dat_compiler_filename
    tree = parse(text, filename)
    compiler.user_routines = {
        str(item.children[0 if item.data == "def_routine" else 1]).upper()
        for item in tree.children
        if isinstance(item, Tree) and item.data in ("def_routine", "def_function")
    }
    compiler.routine_signatures = routine_signatures(tree)
    main = None
    for item in tree.children:
        if not isinstance(item, Tree):
            continue
        if item.data == "def_routine":
            compiler.routine(item, returns=False)
            main = main or str(item.children[0]).upper()
        elif item.data == "def_function":
            compiler.routine(item, returns=True)
        elif item.data == "defdat":
            compiler.data_list(item)
    return Program(filename, compiler, compiler.init_data, main)


def load_file(path: Path) -> Program:
    dat = path.with_suffix(".dat")
    dat_text = dat.read_text(encoding="utf-8") if dat.exists() else None
    return load(path.read_text(encoding="utf-8"), str(path), dat_text)
