"""Shared interpreter core: lark trees compiled once into Python closures, run many times.

Each dialect module (`<dialect>/interpreter.py`) subclasses `Compiler` with its tables (builtins,
comparison operators, index base, literal types) and the few rules its grammar has beyond the
common ones. Numbers are held in the controller's precision (numpy float32 for 32-bit controllers);
pose operations are computed in float64 and stored back in that precision, as the controller stores
them in its variables.
"""

from __future__ import annotations

import math
import operator
from dataclasses import dataclass, field
from functools import cache

import numpy as np
from lark import Lark, Token, Tree
from lark.exceptions import UnexpectedInput

F32 = np.float32
_MISSING = object()
DEFAULT_STEP_LIMIT = 200_000


class RunError(Exception):
    """A program that cannot run on: message starts with file:line:column when known."""


@cache
def grammar_parser(interpreter_file: str, positions: bool = True) -> Lark:
    """The LALR parser of the grammar.lark beside a dialect's interpreter; without positions it
    parses twice as fast (syntax errors still carry them)."""
    return Lark.open("grammar.lark", rel_to=interpreter_file, parser="lalr", propagate_positions=positions)


def parse_with_grammar(interpreter_file: str, text: str, filename: str, positions: bool = True) -> Tree:
    """Parse a program; a syntax error becomes a RunError naming file:line:column."""
    if not text.endswith("\n"):
        text += "\n"
    parser = grammar_parser(interpreter_file, positions)
    try:
        return parser.parse(text)
    except UnexpectedInput as exc:
        raise syntax_error(exc, filename, parser) from None


def syntax_error(exc, filename: str, parser) -> RunError:
    """file:line:column, the token found and what the grammar expected there."""
    names = sorted(getattr(exc, "expected", None) or getattr(exc, "allowed", None) or [])
    patterns = {t.name: t.pattern for t in parser.terminals}
    shown = []
    for name in names:
        pattern = patterns.get(name)
        literal = getattr(pattern, "value", None) if pattern is not None and pattern.type == "str" else None
        shown.append(repr(literal) if literal else name.lower())
    token = getattr(exc, "token", None)
    found = f" at {str(token)!r}" if token is not None and str(token).strip() else ""
    if token is None and getattr(exc, "char", None):
        found = f" at {exc.char!r}"
    expected = ", ".join(shown) if shown else "something else"
    return RunError(f"{filename}:{exc.line}:{exc.column}: syntax error{found}, expected one of {expected}")


class StepLimitError(RunError):
    pass


class Halt(Exception):
    """The program stopped itself (halt / HALT / EXIT / Stop)."""


class Signal:
    """Non-local exits from statements: return, break, continue."""

    __slots__ = ("kind", "value")

    def __init__(self, kind: str, value=None) -> None:
        self.kind = kind
        self.value = value


BREAK = Signal("break")
CONTINUE = Signal("continue")


class Record(dict):
    """A structured value (KRL FRAME/POS, RAPID pose/robtarget, dtrans Point, UR pose)."""

    __slots__ = ("type",)

    def __init__(self, type_name: str, fields=()) -> None:
        super().__init__(fields)
        self.type = type_name

    def copy(self) -> Record:
        return Record(self.type, {k: (v.copy() if isinstance(v, Record | list) else v) for k, v in self.items()})


@dataclass
class MoveEvent:
    kind: str  # "joint" or "linear"
    base2tcp: np.ndarray  # 4x4 float64, mm
    line: int


@dataclass
class Trace:
    messages: list[str] = field(default_factory=list)
    moves: list[MoveEvent] = field(default_factory=list)
    halted: bool = False
    halt_message: str | None = None
    steps: int = 0


def f32(value) -> np.float32:
    return F32(value)


def deepcopy_value(value):
    if isinstance(value, Record | list):
        return value.copy() if isinstance(value, Record) else [deepcopy_value(v) for v in value]
    return value


class Routine:
    """A user procedure or function: parameters, body closure, declared return type."""

    __slots__ = ("body", "decls", "line", "mutated", "name", "params", "return_type")

    def __init__(self, name, params, body, return_type=None, line=0, decls=None) -> None:
        self.name = name
        self.params = params  # list of (name, mode, type or None)
        self.body = body
        self.return_type = return_type
        self.line = line
        self.decls = decls or []  # (name, type, init closure) local declarations
        self.mutated: set[str] | None = None  # names the body assigns into (None: unknown, copy all)


class Frame:
    __slots__ = ("m", "types", "vars")

    def __init__(self, machine: Machine, vars_=None, types=None) -> None:
        self.m = machine
        self.vars = vars_ if vars_ is not None else {}
        self.types = types if types is not None else {}


class Machine:
    """State of one run: globals, injected inputs, trace, step counter."""

    def __init__(self, program: Program, inputs: dict, step_limit: int, camera=None) -> None:
        self.program = program
        self.globals: dict = {}
        self.global_types: dict = {}
        self.inputs = inputs
        self.outputs: dict = {}
        self.camera = camera
        self.trace = Trace()
        self.step_limit = step_limit
        self.steps = 0
        self.extra: dict = {}  # dialect state ($BASE, message handles, ...)

    # --- the vision PC's side of the photo handshake (frame mode) ---------------------------
    def _io_get(self, name: str):
        if name.startswith("input_"):
            return self.inputs.get(name, 0)
        if name.startswith("output_"):
            return self.outputs.get(name, 0)
        return self.globals.get(self.program.compiler.norm(name))

    def _io_set(self, name: str, value) -> None:
        if name.startswith("input_"):
            self.inputs[name] = value
            return
        key = self.program.compiler.norm(name)
        if key not in self.globals:
            raise RunError(f"{self.program.name}: the photo interface variable {name} is not declared")
        self.globals[key] = self.program.compiler.coerce(self.global_types.get(key), value, name)

    def answer_photo(self, where: str) -> bool:
        """If the program has requested a photo that is not answered yet, answer it as the vision PC
        would: take the picture from where the robot last moved, write the reading, acknowledge."""
        io = self.program.photo_io
        if not io:
            return False
        request, ack = self._io_get(io["request"]), self._io_get(io["ack"])
        if request is None or request == ack:
            return False
        if self.camera is None:
            raise RunError(
                f"{where}: the program waits for a photo and no camera is attached "
                "(codegen verify attaches a simulated one)"
            )
        if not self.trace.moves:
            raise RunError(f"{where}: a photo was requested before the robot moved to a photo pose")
        u, v, angle = self.camera.photo(self.trace.moves[-1].base2tcp)
        self._io_set(io["u"], u)
        self._io_set(io["v"], v)
        self._io_set(io["angle"], angle)
        self._io_set(io["ack"], request)
        return True

    def step(self, where: str) -> None:
        self.steps += 1
        if self.steps > self.step_limit:
            raise StepLimitError(f"{where}: step limit {self.step_limit} reached (runaway loop?)")


class Program:
    """A parsed and compiled program, run many times with different inputs.

    `init` (module data, constant definitions) runs once; its globals are kept as a snapshot and
    every run starts from a copy, deep only for the variables the program can change.
    """

    def __init__(self, name: str, compiler: Compiler, init, main: str | None, body=None) -> None:
        self.name = name
        self.compiler = compiler
        self.routines: dict[str, Routine] = compiler.routines
        self.init = init  # closure: module data / constant top-level statements
        self.main = main  # routine to call after init, or None
        self.body = body  # closure run after init when there is no main routine
        self.photo_io: dict | None = None  # names of the photo handshake (set by the loader)
        self._snapshot: tuple[dict, dict, dict] | None = None

    def _prepare(self, step_limit: int) -> tuple[dict, dict, dict]:
        if self._snapshot is None:
            machine = Machine(self, {}, step_limit)
            self.init(Frame(machine, machine.globals, machine.global_types))
            self._snapshot = (machine.globals, machine.global_types, machine.extra)
        return self._snapshot

    def run(self, inputs: dict | None = None, step_limit: int = DEFAULT_STEP_LIMIT, camera=None) -> Trace:
        globals_, types, extra = self._prepare(step_limit)
        machine = Machine(self, dict(inputs or {}), step_limit, camera)
        mutable = self.compiler.assigned_roots
        machine.globals = {k: (deepcopy_value(v) if k in mutable else v) for k, v in globals_.items()}
        machine.global_types = dict(types)
        machine.extra = {k: deepcopy_value(v) for k, v in extra.items()}
        frame = Frame(machine, machine.globals, machine.global_types)
        try:
            self.compiler.inject_inputs(machine)
            if self.main is not None:
                self.compiler.call_routine(frame, self.main, [], {}, "<main>")
            elif self.body is not None:
                signal = self.body(frame)
                if isinstance(signal, Signal) and signal.kind in ("break", "continue"):
                    raise RunError(f"{self.name}: {signal.kind} outside a loop")
        except Halt as halt:
            machine.trace.halted = True
            machine.trace.halt_message = halt.args[0] if halt.args else None
        machine.trace.steps = machine.steps
        return machine.trace


class Compiler:
    """Compile lark trees into closures; dialects override the class attributes and a few rules."""

    name = "base"
    case_insensitive = False
    index_base = 0
    compare_ops = {
        "==": operator.eq,
        "!=": operator.ne,
        "<>": operator.ne,
        "<": operator.lt,
        "<=": operator.le,
        ">": operator.gt,
        ">=": operator.ge,
        "=": operator.eq,
    }
    int_division = False
    assignment_makes_local = False  # URScript: `x = ...` in a function makes a local unless `global`

    def __init__(self, filename: str) -> None:
        self.filename = filename
        self.routines: dict[str, Routine] = {}
        self.builtins = self.make_builtins()
        self.assigned_roots: set[str] = set()  # variables some statement assigns into
        self._routine_assigned: set[str] | None = None  # the same, inside the routine being compiled
        self._pending_refs: list = []  # (callee, argument index, lvalue node, routine-assigned set)
        self.noting_globals = True  # off while compiling statements that run once (constant data)

    # --- tables supplied by dialects ------------------------------------------------------
    def make_builtins(self) -> dict:
        return {}

    def number(self, text: str):
        if any(c in text for c in ".eE"):
            return F32(float(text))
        return int(text)

    def coerce(self, type_name: str | None, value, where: str):
        return value

    def inject_inputs(self, machine: Machine) -> None:
        """Set injected inputs that are program variables (name or name[index])."""
        for name, value in machine.inputs.items():
            key, _, index = name.partition("[")
            key = self.norm(key)
            if key not in machine.globals:
                continue
            if index:
                i = int(index.rstrip("]")) - self.index_base
                seq = machine.globals[key] = list(machine.globals[key])
                seq[i] = self.coerce(self.element_type(machine.global_types.get(key)), value, name)
            else:
                machine.globals[key] = self.coerce(machine.global_types.get(key), value, name)

    def element_type(self, type_name):
        return type_name

    # --- helpers ----------------------------------------------------------------------------
    def norm(self, name: str) -> str:
        return name.upper() if self.case_insensitive else name

    def where(self, node) -> str:
        meta = getattr(node, "meta", None)
        line = getattr(node, "line", None) or (getattr(meta, "line", None) if meta and not meta.empty else None)
        col = getattr(node, "column", None) or (getattr(meta, "column", None) if meta and not meta.empty else None)
        if line is None:
            return self.filename
        return f"{self.filename}:{line}:{col}"

    def line(self, node) -> int:
        meta = getattr(node, "meta", None)
        if isinstance(node, Token):
            return node.line or 0
        return meta.line if meta is not None and not meta.empty else 0

    def fail(self, node, message: str):
        raise RunError(f"{self.where(node)}: {message}")

    # --- expressions ------------------------------------------------------------------------
    def expr(self, node):
        if isinstance(node, Token):
            return self.token_expr(node)
        method = getattr(self, f"e_{node.data}", None)
        if method is None:
            self.fail(node, f"unsupported expression {node.data}")
        return method(node)

    def token_expr(self, token: Token):
        if token.type == "NAME":
            return self.var_reader(token)
        self.fail(token, f"unexpected token {token}")

    def e_number(self, node):
        value = self.number(str(node.children[0]))
        return lambda fr: value

    def e_string(self, node):
        value = self.string_value(str(node.children[0]))
        return lambda fr: value

    def string_value(self, text: str) -> str:
        return text[1:-1]

    def e_true(self, node):
        return lambda fr: True

    def e_false(self, node):
        return lambda fr: False

    def e_var(self, node):
        return self.var_reader(node.children[0])

    def var_reader(self, token):
        key = self.norm(str(token))
        where = self.where(token)

        def read(fr):
            value = fr.vars.get(key, _MISSING)
            if value is _MISSING:
                value = fr.m.globals.get(key, _MISSING)
                if value is _MISSING:
                    raise RunError(f"{where}: undefined variable {token}")
            return value

        return read

    def e_neg(self, node):
        inner = self.expr(node.children[0])
        return lambda fr: -inner(fr)

    def _binary(self, node, op):
        left, right = (self.expr(c) for c in node.children)
        where = self.where(node)

        def run(fr):
            try:
                return op(left(fr), right(fr))
            except ZeroDivisionError:
                raise RunError(f"{where}: division by zero") from None
            except TypeError as exc:
                raise RunError(f"{where}: {exc}") from None

        return run

    def e_add(self, node):
        return self._binary(node, self.add)

    def add(self, a, b):
        return a + b

    def e_sub(self, node):
        return self._binary(node, operator.sub)

    def e_mul(self, node):
        return self._binary(node, operator.mul)

    def e_div(self, node):
        def div(a, b):
            if self.int_division and isinstance(a, int) and isinstance(b, int):
                if b == 0:
                    raise ZeroDivisionError
                return int(a / b)
            if b == 0:
                raise ZeroDivisionError
            return F32(a) / F32(b) if not isinstance(a, float) else a / b

        return self._binary(node, div)

    def e_mod(self, node):
        return self._binary(node, operator.mod)

    # Boolean operators: the operands are the first and last children (KRL and RAPID keep the
    # operator keyword token between them).
    def e_not_(self, node):
        inner = self.expr(node.children[-1])
        return lambda fr: not inner(fr)

    def e_and_(self, node):
        left, right = self.expr(node.children[0]), self.expr(node.children[-1])
        return lambda fr: bool(left(fr)) and bool(right(fr))

    def e_or_(self, node):
        left, right = self.expr(node.children[0]), self.expr(node.children[-1])
        return lambda fr: bool(left(fr)) or bool(right(fr))

    def e_xor(self, node):
        left, right = self.expr(node.children[0]), self.expr(node.children[-1])
        return lambda fr: bool(left(fr)) != bool(right(fr))

    e_exor = e_xor

    def e_compare(self, node):
        left_node, op_token, right_node = node.children
        op = self.compare_ops[str(op_token).upper() if self.case_insensitive else str(op_token)]
        left, right = self.expr(left_node), self.expr(right_node)
        return lambda fr: bool(op(left(fr), right(fr)))

    def e_index(self, node):
        base_node, index_node = node.children
        base, index = self.expr(base_node), self.expr(index_node)
        offset = self.index_base
        where = self.where(node)

        def read(fr):
            seq = base(fr)
            i = int(index(fr)) - offset
            if isinstance(seq, Record):
                seq = list(seq.values())
            if not 0 <= i < len(seq):
                raise RunError(
                    f"{where}: index {i + offset} out of range 1..{len(seq)}"
                    if offset
                    else f"{where}: index {i} out of range 0..{len(seq) - 1}"
                )
            return seq[i]

        return read

    def e_field(self, node):
        base_node, name = node.children
        base = self.expr(base_node)
        key = self.norm(str(name))
        where = self.where(node)

        def read(fr):
            value = base(fr)
            try:
                return value[key]
            except (KeyError, TypeError):
                raise RunError(f"{where}: no field {name} in {getattr(value, 'type', type(value).__name__)}") from None

        return read

    # --- calls ------------------------------------------------------------------------------
    def caller(self, name: str, where: str):
        """call(fr, args, kwargs, setters) for a routine or builtin, resolved at its first call."""
        key = self.norm(name)
        cache: list = []

        def call(fr, args, kwargs, setters=None):
            if not cache:
                routine = self.routines.get(key)
                if routine is not None:
                    cache.append(lambda f, a, k, s: self.invoke(f, routine, a, k, where, s))
                else:
                    builtin = self.builtins.get(key if self.case_insensitive else name)
                    if builtin is None:
                        raise RunError(f"{where}: unknown routine {name}")
                    cache.append(lambda f, a, k, s: builtin(f, a, k, where))
            return cache[0](fr, args, kwargs, setters)

        return call

    def call_routine(self, fr: Frame, name: str, args: list, kwargs: dict, where: str, arg_setters=None):
        key = self.norm(name)
        routine = self.routines.get(key)
        if routine is not None:
            return self.invoke(fr, routine, args, kwargs, where, arg_setters)
        builtin = self.builtins.get(key if self.case_insensitive else name)
        if builtin is None:
            raise RunError(f"{where}: unknown routine {name}")
        return builtin(fr, args, kwargs, where)

    def invoke(self, fr, routine: Routine, args, kwargs, where, arg_setters=None):
        machine = fr.m
        machine.step(where)
        if len(args) != len(routine.params):
            raise RunError(f"{where}: {routine.name} takes {len(routine.params)} arguments, got {len(args)}")
        frame = Frame(machine)
        mutated = routine.mutated
        for (pname, _mode, ptype), value in zip(routine.params, args, strict=True):
            if mutated is None or pname in mutated:
                value = deepcopy_value(value)
            frame.vars[pname] = self.coerce(ptype, value, where) if ptype else value
            if ptype:
                frame.types[pname] = ptype
        for dname, dtype, init in routine.decls:
            if dname in frame.vars:  # a parameter's declaration (KRL): the type only
                frame.types[dname] = dtype
                frame.vars[dname] = self.coerce(dtype, frame.vars[dname], where)
                continue
            frame.types[dname] = dtype
            frame.vars[dname] = init(frame)
        signal = routine.body(frame)
        if arg_setters:
            for (pname, mode, _t), setter in zip(routine.params, arg_setters, strict=True):
                if setter is not None and mode in ("OUT", "INOUT", "VAR", "PERS", "OUT_REF"):
                    setter(fr, frame.vars[pname])
        if isinstance(signal, Signal) and signal.kind == "return":
            value = signal.value
            if routine.return_type:
                return self.coerce(routine.return_type, value, where)
            return value
        if routine.return_type:
            raise RunError(f"{where}: function {routine.name} ended without RETURN")
        return None

    # --- statements -------------------------------------------------------------------------
    def stmt(self, node):
        method = getattr(self, f"s_{node.data}", None)
        if method is None:
            self.fail(node, f"unsupported statement {node.data}")
        return method(node)

    def block(self, nodes) -> callable:
        """Statements in order; each counts one step (charged when the block starts)."""
        trees = [n for n in nodes if isinstance(n, Tree)]
        compiled = [self.stmt(n) for n in trees]
        where = self.where(trees[0]) if trees else self.filename
        count = len(compiled)

        def run(fr):
            machine = fr.m
            machine.steps += count
            if machine.steps > machine.step_limit:
                raise StepLimitError(f"{where}: step limit {machine.step_limit} reached (runaway loop?)")
            for statement in compiled:
                signal = statement(fr)
                if signal is not None:
                    return signal
            return None

        return run

    # Expressions whose value is always newly made, so an assignment need not copy it.
    FRESH = frozenset(
        {
            "add",
            "sub",
            "mul",
            "div",
            "mod",
            "neg",
            "geo",
            "aggregate",
            "list_lit",
            "pose_lit",
            "array_lit",
            "number",
            "string",
            "true",
            "false",
            "compare",
            "and_",
            "or_",
            "not_",
        }
    )

    def s_assign(self, node):
        target, value_node = node.children
        fresh = isinstance(value_node, Tree) and value_node.data in self.FRESH
        setter, value = self.lvalue(target, fresh=fresh), self.expr(value_node)

        def run(fr):
            setter(fr, value(fr))

        return run

    def s_halt_stmt(self, node):
        """halt / HALT / Halt: the program stops; its last message is the operator's message."""

        def run(fr):
            messages = fr.m.trace.messages
            raise Halt(messages[-1] if messages else None)

        return run

    def s_expr_stmt(self, node):
        inner = self.expr(node.children[0])

        def run(fr):
            inner(fr)

        return run

    def s_return_stmt(self, node):
        if node.children and node.children[0] is not None:
            value = self.expr(node.children[0])
            return lambda fr: Signal("return", value(fr))
        return lambda fr: Signal("return", None)

    def s_break_stmt(self, node):
        return lambda fr: BREAK

    def s_continue_stmt(self, node):
        return lambda fr: CONTINUE

    def s_pass_stmt(self, node):
        return lambda fr: None

    def s_while_stmt(self, node):
        cond = self.expr(node.children[0])
        body = self.block(node.children[1].children)
        where = self.where(node)

        def run(fr):
            while cond(fr):
                fr.m.step(where)
                signal = body(fr)
                if signal is BREAK:
                    break
                if signal is CONTINUE:
                    continue
                if signal is not None:
                    return signal
            return None

        return run

    def if_elif(self, node, body_of):
        """IF cond body [ELSEIF cond body]* [ELSE body]: children cond, body, then clauses."""
        cond, body, *rest = node.children
        branches = [(self.expr(cond), body_of(body))]
        else_body = None
        for clause in rest:
            if clause is None:
                continue
            if len(clause.children) == 2:  # elseif / elif clause: condition and body
                branches.append((self.expr(clause.children[0]), body_of(clause.children[1])))
            else:
                else_body = body_of(clause.children[0])
        return self.if_chain(branches, else_body)

    def switch(self, node, body_of):
        """SWITCH / TEST: the first CASE whose value equals the selector, else DEFAULT."""
        selector, *clauses = node.children
        select = self.expr(selector)
        cases, default = [], None
        for clause in clauses:
            if clause is None:
                continue
            if clause.data == "case_clause":
                *values, body = clause.children
                cases.append(([self.expr(v) for v in values], body_of(body)))
            else:
                default = body_of(clause.children[0])

        def run(fr):
            value = select(fr)
            for values, body in cases:
                if any(value == v(fr) for v in values):
                    return body(fr)
            return default(fr) if default is not None else None

        return run

    def wait_until(self, cond_node, where_node, keyword: str):
        """WAIT FOR / WaitUntil: here only the vision PC's answer to a photo request can change a
        condition, so the wait answers a pending request and fails if the condition stays false."""
        cond = self.expr(cond_node)
        where = self.where(where_node)

        def run(fr):
            if not cond(fr) and not (fr.m.answer_photo(where) and cond(fr)):
                raise RunError(f"{where}: {keyword} a condition that nothing here can make true")

        return run

    def if_chain(self, branches, else_body):
        """branches: [(cond closure, body closure)]; else_body closure or None."""

        def run(fr):
            for cond, body in branches:
                if cond(fr):
                    return body(fr)
            if else_body is not None:
                return else_body(fr)
            return None

        return run

    # --- lvalues ----------------------------------------------------------------------------
    def note_assigned(self, node) -> None:
        """Record the variable at the root of an assignment target."""
        whole_variable = isinstance(node, Token) or node.data == "var"
        while isinstance(node, Tree) and node.data != "var":
            node = node.children[0]
        token = node.children[0] if isinstance(node, Tree) else node
        key = self.norm(str(token))
        if self._routine_assigned is not None:
            self._routine_assigned.add(key)
        if self.noting_globals and not (
            whole_variable and self.assignment_makes_local and self._routine_assigned is not None
        ):
            self.assigned_roots.add(key)

    def compile_routine_body(self, routine: Routine, statements) -> None:
        """Compile a routine's statements and note which parameters they assign to."""
        outer, self._routine_assigned = self._routine_assigned, set()
        try:
            routine.body = self.block(statements)
            # every name the body assigns into; finalize() may add by-reference writes later
            routine.mutated = self._routine_assigned
        finally:
            self._routine_assigned = outer

    def ref_setters(self, callee: str, arg_nodes) -> list:
        """Setters for arguments that are variables, used if the callee takes them by reference.

        Whether it does is known once every routine is compiled: see finalize()."""
        setters = []
        for i, node in enumerate(arg_nodes):
            if isinstance(node, Tree) and node.data in ("var", "index", "field", "whole"):
                setters.append(self.lvalue(node, note=False))
                self._pending_refs.append((self.norm(callee), i, node, self._routine_assigned))
            else:
                setters.append(None)
        return setters

    def finalize(self) -> None:
        """Variables passed to by-reference parameters count as assigned."""
        for callee, i, node, routine_assigned in self._pending_refs:
            routine = self.routines.get(callee)
            if routine is None or i >= len(routine.params):
                continue
            if routine.params[i][1] in ("OUT", "INOUT", "VAR", "PERS"):
                outer, self._routine_assigned = self._routine_assigned, routine_assigned
                self.note_assigned(node)
                self._routine_assigned = outer

    def lvalue(self, node, note: bool = True, fresh: bool = False):
        """A setter(frame, value) for a variable, an array element or a record field; fresh: the
        values stored are newly made, so no copy is needed to keep variables from aliasing."""
        if note:
            self.note_assigned(node)
        if isinstance(node, Token) or node.data == "var":
            token = node if isinstance(node, Token) else node.children[0]
            key = self.norm(str(token))
            where = self.where(token)

            def set_var(fr, value):
                if not fresh and isinstance(value, Record | list):
                    value = deepcopy_value(value)  # value semantics: no aliasing between variables
                if key in fr.vars:
                    fr.vars[key] = self.coerce(fr.types.get(key), value, where)
                elif key in fr.m.globals:
                    fr.m.globals[key] = self.coerce(fr.m.global_types.get(key), value, where)
                else:
                    self.new_variable(fr, key, value, where)

            return set_var
        if node.data == "index":
            base_node, index_node = node.children
            base, index = self.expr(base_node), self.expr(index_node)
            offset = self.index_base
            where = self.where(node)

            def set_item(fr, value):
                seq = base(fr)
                i = int(index(fr)) - offset
                if not isinstance(seq, list) or not 0 <= i < len(seq):
                    raise RunError(f"{where}: index {i + offset} out of range")
                seq[i] = self.coerce_like(seq[i], value, where)

            return set_item
        if node.data == "field":
            base_node, name = node.children
            base = self.expr(base_node)
            key = self.norm(str(name))
            where = self.where(node)

            def set_field(fr, value):
                record = base(fr)
                if not isinstance(record, Record) or key not in record:
                    raise RunError(f"{where}: no field {name} in {getattr(record, 'type', '?')}")
                record[key] = self.coerce_like(record[key], value, where)

            return set_field
        self.fail(node, f"cannot assign to {node.data}")

    def new_variable(self, fr, key, value, where):
        fr.vars[key] = value

    def coerce_like(self, old, value, where):
        """Store value where old was: keep the slot's number type."""
        if isinstance(old, np.floating) and not isinstance(value, bool):
            try:
                return F32(value)
            except (TypeError, ValueError):
                raise RunError(f"{where}: cannot store {value!r} in a number") from None
        if isinstance(old, Record) and isinstance(value, Record):
            return value.copy()
        return deepcopy_value(value)


# --- number formatting shared by message instructions -----------------------------------------


def format_fixed(value, decimals: int) -> str:
    """Fixed decimals with round-half-away-from-zero as controllers display, no '-0'."""
    v = float(value)
    if not math.isfinite(v):
        return "nan" if math.isnan(v) else ("inf" if v > 0 else "-inf")
    scaled = abs(v) * 10**decimals
    rounded = math.floor(scaled + 0.5) / 10**decimals
    text = f"{math.copysign(rounded, v):.{decimals}f}"
    if text.lstrip("-").strip("0.") == "":
        text = text.lstrip("-")
    return text


def format_general(value) -> str:
    """Shortest text that reads back to the same float32 (ints as ints)."""
    if isinstance(value, bool):
        return "True" if value else "False"
    if isinstance(value, int | np.integer):
        return str(int(value))
    v = F32(value)
    if not np.isfinite(v):
        return "nan" if np.isnan(v) else ("inf" if v > 0 else "-inf")
    return np.format_float_positional(v, trim="-", unique=True)
