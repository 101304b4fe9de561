"""RAPID interpreter: num in float32, trig in degrees, pose/robtarget records and Pose* functions."""

from __future__ import annotations

import math
import re

from lark import Token, Tree

from codegen.dialects.core.compiler import Compiler
from codegen.dialects.core.machine import Program
from codegen.dialects.core.parsing import parse_with_grammar
from codegen.dialects.core.source import Inline, Src, indent
from codegen.dialects.core.values import F32, Record, RunError, constant, f32
from codegen.dialects.rapid import errors, interrupts, messages, search, waits
from codegen.dialects.rapid.builtins import RECORDS, builtins, num, type_text, zero
from codegen.dialects.rapid.messages import PREDEFINED_VALUES


def parse(text: str, filename: str = "<rapid>", positions: bool = True) -> Tree:
    return parse_with_grammar(__file__, text, filename, positions)


_PREDEFINED = re.compile(r"^(V\d+|VMAX|FINE|Z\d+|TOOL0|WOBJ0|LOAD0)$")


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
        self.handler = None  # the routine being compiled: its ERROR handler (compiled) and numbers
        self.in_handler = False  # compiling an error handler's statements
        self.handler_node = None  # the routine being compiled: its error_clause node
        self.ns["_divzero"] = errors.divzero
        self.storage: dict[str, str] = {}  # the module's data: VAR, PERS or CONST by name
        self.trap_names: set[str] = set()  # the module's TRAP routines (known before any routine is compiled)
        self.traps: dict = {}  # TRAP routines by key: run by their interrupts only (interrupts.py)

    # --- tables ------------------------------------------------------------------------------
    def make_builtins(self) -> dict:
        return builtins(self)

    def number(self, text: str):
        return f32(float(text))

    def string_value(self, text: str) -> str:
        return text[1:-1].replace('""', '"').replace("\\\\", "\\")

    def coerce(self, type_name, value, where):
        if type_name is None:
            return value
        if type_name == "NUM":
            return value if type(value) is F32 else f32(num(value, where))
        if isinstance(type_name, tuple):  # (element type, size) array
            return self.coerce_array(type_name, value, where, type_name[0].lower())
        if type_name == "DNUM":
            return float(num(value, where))
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

    def inject_inputs(self, machine) -> None:
        """A run starts at main, as after PP to Main: the module's VAR data get their initial values
        again and only PERS data keep a value from before the run (RAPID overview, program data:
        persistents), so an input may only preset PERS data."""
        for name in machine.inputs:
            key, _index = self._input_names.get(name) or self._input_name(name)
            storage = self.storage.get(key)
            if key in machine.globals and storage not in (None, "PERS"):
                raise RunError(f"input {name}: {storage} data gets its initial value at each start (PERS keeps one)")
        super().inject_inputs(machine)

    # --- expressions -------------------------------------------------------------------------
    def var_reader(self, token):
        key = self.norm(name := str(token))  # the reader keeps the name: a kept token keeps the parse tree's memory
        where = self.where(token)
        predefined = key if _PREDEFINED.match(key) else PREDEFINED_VALUES.get(key)
        if predefined is None:
            predefined = errors.ERROR_CONSTANTS.get(key)

        def read(fr):
            if key in fr.vars:
                return fr.vars[key]
            if key in fr.m.globals:
                return fr.m.globals[key]
            if predefined is not None:
                return predefined
            if key == "ERRNO":  # the system variable: the most recent error's number
                return fr.m.extra.get("ERRNO", f32(0))
            raise RunError(f"{where}: undefined variable {name}")

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
        signal = waits.signal_function(self, node, str(name), args_node)
        if signal is not None:
            return signal
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

    def guarded(self, lines, where):
        """As the base's, but a division by zero is the RAPID error ERR_DIVZERO, which a routine's
        error handler may take (RAPID overview, Error Recovery: "division by zero" is its example)."""
        return [
            "try:",
            *indent(lines),
            "except ZeroDivisionError:",
            f"    raise _divzero({where!r}) from None",
            "except (TypeError, ValueError, OverflowError) as _e:",
            f"    raise _operror({where!r}, _e) from None",
        ]

    # --- statements --------------------------------------------------------------------------
    def stmt(self, node):
        """A statement of a routine with an ERROR handler runs under it (errors.protect)."""
        compiled = super().stmt(node)
        if self.handler is None or self.in_handler:
            return compiled
        handler, errnos = self.handler
        return errors.protect(compiled, handler, errnos, self.where(node))

    def s_proc_call(self, node):
        name, args_node = node.children
        key = str(name).upper()
        if key in self.trap_names:
            self.fail(node, f"{name} is a TRAP routine: it runs when its interrupt comes (CONNECT), it is not called")
        special = SPECIAL.get(key)
        if special is not None:
            return special(self, node, args_node)
        return self.s_call_stmt(node)

    def s_connect_stmt(self, node):
        return interrupts.connect(self, node)

    def s_raise_stmt(self, node):
        """RAISE errno outside a handler; RAISE in a handler passes its error (or a new one) to the caller."""
        where = self.where(node)
        value_node = node.children[0]
        if value_node is None:
            if not self.in_handler:
                self.fail(node, "RAISE without an error number outside an error handler")

            def reraise(fr):
                error = errors.current_error(fr, where)
                error.leaving = fr
                raise error

            return reraise
        value = self.expr(value_node)
        name = str(value_node.children[0]) if isinstance(value_node, Tree) and value_node.data == "var" else None
        in_handler = self.in_handler

        def raise_(fr):
            error = errors.raise_error(fr, value(fr), where, name)
            if in_handler:
                error.leaving = fr
            raise error

        return raise_

    def s_retry_stmt(self, node):
        return self.handler_signal(node, "retry", "RETRY")

    def s_trynext_stmt(self, node):
        return self.handler_signal(node, "trynext", "TRYNEXT")

    def handler_signal(self, node, kind: str, keyword: str):
        if not self.in_handler:
            self.fail(node, f"{keyword} outside an error handler")
        return Inline(self, [f"return _Signal({kind!r})"])

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
        handler = node.children[-1]
        self.handler_node = handler if isinstance(handler, Tree) and handler.data == "error_clause" else None
        children = [
            c
            for c in node.children
            if not (isinstance(c, Token) and c.type == "LOCAL") and c is not None and c is not self.handler_node
        ]
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

    def compile_routine_body(self, routine, statements, local_types=None) -> None:
        """The body, and its ERROR handler first (in the routine's scope: its data covers the handler)."""
        self.local_types, self.routine_name = local_types, routine.name
        try:
            clause = self.handler_node
            if clause is not None:
                numbers_node, body = clause.children
                self.in_handler = True
                try:
                    handler = self.body_block(body)
                    errnos = None
                    if numbers_node is not None:
                        exprs = [self.expr(e) for e in numbers_node.children]

                        def errnos(fr, exprs=exprs):
                            return {int(float(e(fr))) for e in exprs}

                finally:
                    self.in_handler = False
                self.handler = (handler, errnos)
            routine.body = self.block(statements)
        finally:
            self.local_types, self.routine_name = None, "module"
            self.handler, self.handler_node = None, None

    def call_routine(self, fr, name, args, kwargs, where, arg_setters=None):
        """The entry routine: an error no handler took ends the run (errors.unhandled)."""
        try:
            return super().call_routine(fr, name, args, kwargs, where, arg_setters)
        except errors.RapidError as error:
            if where != "<main>":
                raise
            errors.unhandled(error)

    def _local_init(self, node, static_type, make):
        """A local's initialiser: its zero value shared by every call when it has no initial
        value and a known size (values are never changed in place)."""
        if node.children[-1] is None and static_type is not None:
            if isinstance(static_type, tuple):
                return constant([zero(static_type[0])] * static_type[1])
            return constant(zero(static_type))
        return lambda fr: make(fr)[1]


SPECIAL = {  # instructions compiled from their argument nodes (names, variables written, switches)
    **waits.SPECIAL,
    **interrupts.SPECIAL,
    "UIMSGBOX": messages.ui_msg_box,
    "SEARCHL": search.search_l,
}


def _routine_name(item) -> str:
    named = [c for c in item.children if c is not None and not (isinstance(c, Token) and c.type == "LOCAL")]
    return str(named[1 if item.data == "func" else 0])


def load(text: str, filename: str = "<rapid>") -> Program:
    tree = parse(text, filename)
    compiler = RAPIDCompiler(filename)
    module = tree.children[0]
    compiler.user_routines = set()
    seen = set()
    for item in module.children:
        if isinstance(item, Tree) and item.data in ("proc", "func", "trap"):
            name = _routine_name(item)
            if name.upper() in seen:
                compiler.fail(item, f"routine {name} defined twice")
            seen.add(name.upper())
            (compiler.trap_names if item.data == "trap" else compiler.user_routines).add(name.upper())
    data = []
    for item in module.children:
        if not isinstance(item, Tree):
            continue
        if item.data == "data_decl":
            key = str(item.children[4]).upper()
            if key in compiler.storage:  # names are case-insensitive: LSR_X and lsr_x are one datum
                compiler.fail(item, f"{item.children[4]} declared twice in the module (names ignore case)")
            if key in seen:  # one name, one object in a scope (RAPID overview, scope rules; recalled)
                compiler.fail(item, f"{item.children[4]} names both data and a routine (names ignore case)")
            data.append(compiler.decl(item))
            compiler.storage[key] = str(item.children[2]).upper()
        elif item.data == "proc":
            compiler.routine(item, returns=False)
        elif item.data == "func":
            compiler.routine(item, returns=True)
        elif item.data == "trap":  # compiled as a procedure without parameters, kept apart: never called
            compiler.routine(item, returns=False)
            key = _routine_name(item).upper()
            compiler.traps[key] = compiler.routines.pop(key)
    if "MAIN" not in compiler.routines:
        raise RunError(f"{filename}: no PROC main")

    def init(fr):
        for key, make in data:
            type_name, value = make(fr)
            fr.m.global_types[key] = type_name
            fr.m.globals[key] = value

    return Program(str(module.children[0]), compiler, init, "MAIN")
