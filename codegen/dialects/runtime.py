"""Shared interpreter core: lark trees compiled once into Python functions, run many times.

Expressions and simple statements are compiled to Python source (`Src`, `Inline`) and a routine's
block becomes one Python function; rules without a source form stay closures, which the generated
code calls. Both share the same helpers (coercions, builtins, routine calls), so the semantics do
not depend on which form a rule has.

Each dialect module (`<dialect>/interpreter.py`) subclasses `Compiler` with its tables (builtins,
comparison operators, index base, literal types) and the few rules its grammar has beyond the
common ones. Numbers are held in the controller's precision (numpy float32 for 32-bit controllers);
pose operations are computed in float64 and stored back in that precision, as the controller stores
them in its variables.
"""

from __future__ import annotations

import builtins
import math
import operator
import re
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
    """A structured value (KRL FRAME/POS, RAPID pose/robtarget, dtrans Point, UR pose).

    Records and arrays are never changed in place once made: assigning to a field or an element
    stores a changed copy along the path (see Compiler.lvalue). So variables can share values
    without copying, and still behave as the controllers' value semantics say."""

    __slots__ = ("type",)

    def __init__(self, type_name: str, fields=()) -> None:
        super().__init__(fields)
        self.type = type_name

    def copy(self) -> Record:
        return Record(self.type, {k: (v.copy() if isinstance(v, Record | list) else v) for k, v in self.items()})

    def shallow(self) -> Record:
        """A new record of the same class with the same field values (to change one of them)."""
        new = dict.__new__(type(self))
        dict.update(new, self)
        new.type = self.type
        return new


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


_ONE32 = F32(1.0)
_WEAK_PYTHON_FLOATS = type(_ONE32 * 0.1) is F32  # NumPy >= 2 (NEP 50)


def f32(value) -> np.float32:
    """value rounded to float32, exactly as F32(value). A Python float takes a path six times
    faster: under NEP 50 it is first rounded to float32, and x 1.0 in float32 is exact (sign of
    zero, inf and NaN included; overflow warns as F32 does)."""
    if _WEAK_PYTHON_FLOATS and type(value) is float:
        return _ONE32 * value
    return F32(value)


class Src(str):
    """Python source of an expression. It may use `fr` (the frame), `m` (the machine), `V` (the
    frame's variables), `G` (the globals) and the names the compiler registered with const()."""


class Inline:
    """A statement as Python source lines: block() inlines them; called directly, the lines are
    compiled once into a function. The lines end a block with `return signal` for RETURN, EXIT..."""

    __slots__ = ("compiler", "fn", "lines")

    def __init__(self, compiler: Compiler, lines: list[str]) -> None:
        self.compiler = compiler
        self.lines = lines
        self.fn = None

    def __call__(self, fr):
        if self.fn is None:
            self.fn = self.compiler.function([*self.lines, "return None"])
        return self.fn(fr)


class LazyStore:
    """A by-reference argument's setter, compiled (in the context of the routine that passes the
    argument) only when a callee writes it back: most arguments are passed by value."""

    __slots__ = ("compiler", "context", "fn", "node")

    def __init__(self, compiler: Compiler, node) -> None:
        self.compiler, self.node, self.fn = compiler, node, None
        self.context = (compiler.local_types, compiler.routine_name)

    def __call__(self, fr, value) -> None:
        if self.fn is None:
            compiler = self.compiler
            saved = compiler.local_types, compiler.routine_name
            compiler.local_types, compiler.routine_name = self.context
            try:
                self.fn = compiler.lvalue(self.node)
            finally:
                compiler.local_types, compiler.routine_name = saved
        self.fn(fr, value)


def halt(fr, *_ignored) -> None:
    """Stop the program; its last message is the operator's message (HALT, EXIT, Stop, halt())."""
    messages = fr.m.trace.messages
    raise Halt(messages[-1] if messages else None)


def constant(value):
    """An initialiser that gives every run the same value (safe: values are never changed in place);
    compiled routine entries store `.value` directly."""

    def initial(fr):
        return value

    initial.value = value
    return initial


def op_error(where: str, exc: Exception) -> RunError:
    """An operator applied to values it does not take, as the controller would refuse it."""
    if isinstance(exc, ZeroDivisionError):
        return RunError(f"{where}: division by zero")
    if isinstance(exc, ValueError | OverflowError):  # int(nan), int(inf) as an index...
        return RunError(f"{where}: invalid value ({exc})")
    return RunError(f"{where}: type mismatch ({exc})")


def step_limit_error(where: str, machine: Machine) -> StepLimitError:
    return StepLimitError(f"{where}: step limit {machine.step_limit} reached (runaway loop?)")


def index_value(seq, index, offset: int, where: str):
    """seq[index] with the controller's index base; a record is indexed by its field order."""
    i = int(index) - offset
    if isinstance(seq, Record):
        seq = list(seq.values())
    if not 0 <= i < len(seq):
        raise RunError(
            f"{where}: index {i + offset} out of range 1..{len(seq)}"
            if offset
            else f"{where}: index {i} out of range 0..{len(seq) - 1}"
        )
    return seq[i]


def no_field(value, name: str, where: str):
    raise RunError(f"{where}: no field {name} in {getattr(value, 'type', type(value).__name__)}")


def no_field_to_set(value, name: str, where: str):
    raise RunError(f"{where}: no field {name} in {getattr(value, 'type', '?')}")


def bad_index(index: int, where: str):
    raise RunError(f"{where}: index {index} out of range")


_FRAME_NAMES = re.compile(r"\b(m|V|G)\b")


def indent(lines: list[str]) -> list[str]:
    return ["    " + line for line in lines]


class Routine:
    """A user procedure or function: parameters, compiled body, declared return type."""

    __slots__ = ("body", "decls", "entry", "line", "name", "params", "return_type")

    def __init__(self, name, params, body, return_type=None, line=0, decls=None) -> None:
        self.name = name
        self.params = params  # list of (name, mode, type or None)
        self.body = body
        self.return_type = return_type
        self.line = line
        self.decls = decls or []  # (name, type, init closure) local declarations
        self.entry = None  # the compiled call (Compiler.entry)


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
    every run starts from a shallow copy of it (values are never changed in place).
    """

    def __init__(self, name: str, compiler: Compiler, init, main: str | None, body=None) -> None:
        self.name = name
        self.compiler = compiler
        self.routines: dict[str, Routine] = compiler.routines
        self.init = init  # callable: module data / constant top-level statements
        self.main = main  # routine to call after init, or None
        self.body = body  # callable run after init when there is no main routine
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
        machine.globals = dict(globals_)  # values are never changed in place: sharing them is safe
        machine.global_types = dict(types)
        machine.extra = dict(extra)
        frame = Frame(machine, machine.globals, machine.global_types)
        try:
            self.compiler.inject_inputs(machine)
            if self.main is not None:
                self.compiler.call_routine(frame, self.main, [], {}, "<main>")
            elif self.body is not None:
                signal = self.body(frame)
                if isinstance(signal, Signal) and signal.kind in ("break", "continue"):
                    raise RunError(f"{self.name}: {signal.kind} outside a loop")
        except RecursionError:
            raise RunError(f"{self.name}: routine calls nested too deeply (runaway recursion?)") from None
        except Halt as halt:
            machine.trace.halted = True
            machine.trace.halt_message = halt.args[0] if halt.args else None
        machine.trace.steps = machine.steps
        return machine.trace


class Compiler:
    """Compile lark trees into Python source (closures where a rule has no source form); dialects
    override the class attributes (tables) and a few rules."""

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

    def __init__(self, filename: str) -> None:
        self.filename = filename
        self.routines: dict[str, Routine] = {}
        self.builtins = self.make_builtins()
        self.ns: dict = {  # the globals of the generated Python source
            "__builtins__": builtins,
            "_Signal": Signal,
            "_BREAK": BREAK,
            "_CONTINUE": CONTINUE,
            "_operror": op_error,
            "_steplimit": step_limit_error,
            "_index": index_value,
            "_nofield": no_field,
            "_nofield_set": no_field_to_set,
            "_badindex": bad_index,
            "_Record": Record,
            "_F32": F32,
            "_Frame": Frame,
            "_RunError": RunError,
        }
        self.local_types: dict | None = None  # the routine being compiled: its variables' types
        self.routine_name = "module"
        self.user_routines: set[str] | None = None  # every routine of the program, when known up front
        self._consts: dict[int, str] = {}
        self._temps = 0
        self._source_depth = 0
        self._input_names: dict[str, tuple[str, int | None]] = {}

    # --- Python source ----------------------------------------------------------------------
    def temp(self) -> str:
        """A fresh local name for a value used twice within one expression."""
        self._temps += 1
        return f"_w{self._temps}"

    def const(self, value) -> str:
        """A name under which the generated source sees value (a closure, a number, a table)."""
        name = self._consts.get(id(value))
        if name is None or self.ns[name] is not value:
            name = f"_k{len(self.ns)}"
            self.ns[name] = value
            self._consts[id(value)] = name
        return name

    def function(self, lines: list[str], params: str = "fr", name: str | None = None, prologue: bool = True):
        """Compile statement lines into a function (of the frame `fr` unless params say more); the
        prologue binds m, V and G where the lines use them."""
        head = []
        if prologue:
            used = set(_FRAME_NAMES.findall("\n".join(lines)))
            if "m" in used or "G" in used:
                head.append("m = fr.m")
            if "V" in used:
                head.append("V = fr.vars")
            if "G" in used:
                head.append("G = m.globals")
        name = re.sub(r"\W", "_", name or f"{self.name}_{self.routine_name}")  # shows in tracebacks and profiles
        text = "\n".join([f"def {name}({params}):", *indent(head), *indent(lines)]) + "\n"
        scope: dict = {}
        exec(compile(text, f"<{self.filename}: compiled>", "exec"), self.ns, scope)
        return scope[name]

    def guarded(self, lines: list[str], where: str) -> list[str]:
        """Lines whose operator errors (a number plus a string, a division by zero, a NaN index)
        become RunErrors naming the statement."""
        return [
            "try:",
            *indent(lines),
            "except (TypeError, ZeroDivisionError, ValueError, OverflowError) as _e:",
            f"    raise _operror({where!r}, _e) from None",
        ]

    MAX_SOURCE_DEPTH = 24  # expression levels inline before a subexpression gets its own function

    def src(self, node) -> Src:
        """The Python source of an expression; a rule without one is called as its closure. A deep
        subexpression is compiled into a function of its own (Python limits nesting in source)."""
        if self._source_depth >= self.MAX_SOURCE_DEPTH:
            outer, self._source_depth = self._source_depth, 0
            try:
                return Src(f"{self.const(self.expr(node))}(fr)")
            finally:
                self._source_depth = outer
        self._source_depth += 1
        try:
            compiled = self._compile_expr(node)
        finally:
            self._source_depth -= 1
        return compiled if isinstance(compiled, Src) else Src(f"{self.const(compiled)}(fr)")

    def source_of(self, compiled) -> Src:
        """Source of what expr() or stmt() returned: inline text or a call of the closure."""
        source = getattr(compiled, "source", None)
        return source if source is not None else Src(f"{self.const(compiled)}(fr)")

    def body_lines(self, compiled) -> list[str]:
        """Lines that run a compiled statement or block inline and pass its signal on."""
        if isinstance(compiled, Inline):
            return compiled.lines
        inline = getattr(compiled, "inline", None)
        if (
            inline is not None
            and max((len(x) - len(x.lstrip(" ")) for x in inline), default=0) < self.MAX_INLINE_INDENT
        ):
            return inline
        return [f"_s = {self.const(compiled)}(fr)", "if _s is not None:", "    return _s"]

    # A block nested deeper than this is called rather than inlined (Python allows 20 nested
    # try blocks and 100 indentation levels in one function).
    MAX_INLINE_INDENT = 4 * 12

    # --- tables supplied by dialects ------------------------------------------------------
    def make_builtins(self) -> dict:
        return {}

    def number(self, text: str):
        if any(c in text for c in ".eE"):
            return f32(float(text))
        return int(text)

    def coerce(self, type_name: str | None, value, where: str):
        return value

    def inject_inputs(self, machine: Machine) -> None:
        """Set injected inputs that are program variables (name or name[index])."""
        for name, value in machine.inputs.items():
            key, index = self._input_names.get(name) or self._input_name(name)
            if key not in machine.globals:
                continue
            if index is not None:
                i = index - self.index_base
                seq = machine.globals[key] = list(machine.globals[key])
                seq[i] = self.coerce(self.element_type(machine.global_types.get(key)), value, name)
            else:
                machine.globals[key] = self.coerce(machine.global_types.get(key), value, name)

    def _input_name(self, name: str) -> tuple[str, int | None]:
        """An input's variable and element index, parsed once per name."""
        key, _, index = name.partition("[")
        parsed = (self.norm(key), int(index.rstrip("]")) if index else None)
        self._input_names[name] = parsed
        return parsed

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
        """A callable fr -> value; when the rule has a source form, `.source` holds it."""
        compiled = self._compile_expr(node)
        if not isinstance(compiled, Src):
            return compiled
        fn = self.function(self.guarded([f"return {compiled}"], self.where(node)))
        fn.source = compiled
        return fn

    def _compile_expr(self, node):
        if isinstance(node, Token):
            compiled = self.token_expr(node)
        else:
            method = getattr(self, f"e_{node.data}", None)
            if method is None:
                self.fail(node, f"unsupported expression {node.data}")
            compiled = method(node)
        source = getattr(compiled, "source", None)
        return source if source is not None else compiled

    def token_expr(self, token: Token):
        if token.type == "NAME":
            return self.var_source(token)
        self.fail(token, f"unexpected token {token}")

    def e_number(self, node):
        return Src(self.const(self.number(str(node.children[0]))))

    def e_string(self, node):
        return Src(repr(self.string_value(str(node.children[0]))))

    def string_value(self, text: str) -> str:
        return text[1:-1]

    def e_true(self, node):
        return Src("True")

    def e_false(self, node):
        return Src("False")

    def e_var(self, node):
        return self.var_source(node.children[0])

    def var_source(self, token) -> Src:
        """A routine's variables, then the globals; anything else (errors, the controller's own
        names) is left to the dialect's var_reader."""
        key = repr(self.norm(str(token)))
        if self.local_types is not None and self.norm(str(token)) in self.local_types:
            return Src(f"V[{key}]")  # a declared local or parameter: always in the frame
        fallback = self.const(self.var_reader(token))
        return Src(f"(V[{key}] if {key} in V else G[{key}] if {key} in G else {fallback}(fr))")

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
        return Src(f"(-{self.src(node.children[0])})")

    def _binary_source(self, node, symbol: str) -> Src:
        left, right = (self.src(c) for c in node.children)
        return Src(f"({left} {symbol} {right})")

    def _binary_call(self, node, function) -> Src:
        left, right = (self.src(c) for c in node.children)
        return Src(f"{self.const(function)}({left}, {right})")

    def e_add(self, node):
        if type(self).add is Compiler.add:
            return self._binary_source(node, "+")
        return self._binary_call(node, self.add)

    def add(self, a, b):
        return a + b

    def e_sub(self, node):
        return self._binary_source(node, "-")

    def e_mul(self, node):
        return self._binary_source(node, "*")

    def e_div(self, node):
        return self._binary_call(node, self.divide)

    def divide(self, a, b):
        if self.int_division and isinstance(a, int) and isinstance(b, int):
            if b == 0:
                raise ZeroDivisionError
            return int(a / b)
        if b == 0:
            raise ZeroDivisionError
        return f32(a) / f32(b) if not isinstance(a, float) else a / b

    def e_mod(self, node):
        return self._binary_source(node, "%")

    # Boolean operators: the operands are the first and last children (KRL and RAPID keep the
    # operator keyword token between them). Results are Python bools.
    def e_not_(self, node):
        return Src(f"(not {self.src(node.children[-1])})")

    def e_and_(self, node):
        left, right = self.src(node.children[0]), self.src(node.children[-1])
        return Src(f"(True if {left} and {right} else False)")

    def e_or_(self, node):
        left, right = self.src(node.children[0]), self.src(node.children[-1])
        return Src(f"(True if {left} or {right} else False)")

    def e_xor(self, node):
        left, right = self.src(node.children[0]), self.src(node.children[-1])
        return Src(f"(bool({left}) != bool({right}))")

    e_exor = e_xor

    OPERATOR_SYMBOLS = {
        operator.eq: "==",
        operator.ne: "!=",
        operator.lt: "<",
        operator.le: "<=",
        operator.gt: ">",
        operator.ge: ">=",
    }

    def e_compare(self, node):
        left_node, op_token, right_node = node.children
        op = self.compare_ops[str(op_token).upper() if self.case_insensitive else str(op_token)]
        left, right = self.src(left_node), self.src(right_node)
        symbol = self.OPERATOR_SYMBOLS.get(op)
        if symbol is None:
            return Src(f"(True if {self.const(op)}({left}, {right}) else False)")
        return Src(f"(True if {left} {symbol} {right} else False)")

    def e_index(self, node):
        """An array element inline; anything else (a record's field by number, an index out of
        range) through index_value()."""
        base_node, index_node = node.children
        seq, i, offset = self.temp(), self.temp(), self.index_base
        base, index = self.src(base_node), self.index_source(index_node)
        return Src(
            f"({seq}[{i}] if ((type({seq} := {base}) is list) & (({i} := {index}) >= 0)) and {i} < len({seq})"
            f" else _index({seq}, {i} + {offset}, {offset}, {self.where(node)!r}))"
        )

    def index_source(self, index_node) -> str:
        """Source of a 0-based index; a literal index is folded into a number."""
        if isinstance(index_node, Tree) and index_node.data == "number":
            value = self.number(str(index_node.children[0]))
            if float(value) == int(value):
                return str(int(value) - self.index_base)
        return f"int({self.src(index_node)}) - {self.index_base}"

    def e_field(self, node):
        base_node, name = node.children
        base = self.src(base_node)
        key = repr(self.norm(str(name)))
        return Src(
            f"(_t[{key}] if isinstance(_t := {base}, dict) and {key} in _t "
            f"else _nofield(_t, {str(name)!r}, {self.where(node)!r}))"
        )

    # --- calls ------------------------------------------------------------------------------
    def call_source(self, name: str, args: list[str], kwargs: dict[str, str], setters, where: str) -> Src:
        """A call of a routine or builtin; the name is resolved at the first call (routines may be
        defined after their callers), then the generated code calls the target directly."""
        key = self.norm(name)
        slot = f"_c{len(self.ns)}"
        if self.user_routines is not None and key not in self.user_routines:
            setters = None  # a builtin: arguments are never written back
        with_setters = setters is not None and any(setters)

        def resolve(fr, a, k, w, s=None):
            target = self.resolve_call(key, name, w, with_setters)
            self.ns[slot] = target
            return target(fr, a, k, w, s) if with_setters else target(fr, a, k, w)

        self.ns[slot] = resolve
        kw = "{" + ", ".join(f"{k!r}: {v}" for k, v in kwargs.items()) + "}"
        tail = f", {self.const(setters)}" if with_setters else ""
        return Src(f"{slot}(fr, [{', '.join(args)}], {kw}, {where!r}{tail})")

    def resolve_call(self, key: str, name: str, where: str, with_setters: bool):
        routine = self.routines.get(key)
        if routine is not None:
            return self.entry(routine)
        builtin = self.builtins.get(key if self.case_insensitive else name)
        if builtin is None:
            raise RunError(f"{where}: unknown routine {name}")
        if with_setters:
            return lambda fr, a, k, w, s: builtin(fr, a, k, w)
        return builtin

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
        return self.entry(routine)(fr, args, kwargs, where, arg_setters)

    BY_REFERENCE = ("OUT", "INOUT", "VAR", "PERS", "OUT_REF")
    KWARGS_ERROR: str | None = None  # message when a user routine is called with named arguments

    def entry(self, routine: Routine):
        """The routine's call as one compiled function (fr, args, kwargs, where, setters): count
        the step, check and coerce the arguments, make the locals, run the body, write
        by-reference arguments back, coerce the returned value."""
        if routine.entry is not None:
            return routine.entry
        name, count = routine.name, len(routine.params)
        lines = [
            "m = fr.m",
            "m.steps += 1",
            "if m.steps > m.step_limit: raise _steplimit(w, m)",
            f"if len(a) != {count}:",
            f"    raise _RunError(f'{{w}}: {name} takes {count} arguments, got {{len(a)}}')",
        ]
        if self.KWARGS_ERROR:
            lines += ["if k:", f"    raise _RunError(f'{{w}}: {name} {self.KWARGS_ERROR}')"]
        lines += ["f = _Frame(m)", "V = f.vars", "T = f.types"]
        for i, (pname, _mode, ptype) in enumerate(routine.params):
            lines.append(f"_p = a[{i}]")
            lines.append(f"V[{pname!r}] = {self.coerce_source(ptype, '_p', 'w')}")
            if ptype:
                lines.append(f"T[{pname!r}] = {self.const(ptype)}")
        for dname, dtype, init in routine.decls:
            lines.append(f"T[{dname!r}] = {self.const(dtype)}")
            if hasattr(init, "value"):  # constant(): the same value for every call
                lines.append(f"V[{dname!r}] = {self.const(init.value)}")
            else:
                lines.append(f"V[{dname!r}] = {self.const(init)}(f)")
        lines.append(f"_s = {self.const(routine.body)}(f)")
        refs = [(i, p) for i, (p, mode, _t) in enumerate(routine.params) if mode in self.BY_REFERENCE]
        if refs:
            lines.append("if s:")
            for i, pname in refs:
                lines.append(f"    if s[{i}] is not None: s[{i}](fr, V[{pname!r}])")
        lines.append("if _s is not None and _s.kind == 'return':")
        if routine.return_type:
            lines += ["    _p = _s.value", f"    return {self.coerce_source(routine.return_type, '_p', 'w')}"]
            lines.append(f"raise _RunError(f'{{w}}: function {name} ended without RETURN')")
        else:
            lines += ["    return _s.value", "return None"]
        routine.entry = self.function(lines, "fr, a, k, w, s=None", f"{self.name}_{name}_call", prologue=False)
        return routine.entry

    # --- statements -------------------------------------------------------------------------
    def stmt(self, node):
        method = getattr(self, f"s_{node.data}", None)
        if method is None:
            self.fail(node, f"unsupported statement {node.data}")
        return method(node)

    def block(self, nodes) -> callable:
        """Statements in order, compiled into one function; each counts one step (charged when the
        block starts). The function returns a Signal (return, break, ...) or None; `.inline`
        holds its lines for inlining into an enclosing block."""
        trees = [n for n in nodes if isinstance(n, Tree)]
        compiled = [self.stmt(n) for n in trees]
        where = self.where(trees[0]) if trees else self.filename
        lines = [f"m.steps += {len(compiled)}", f"if m.steps > m.step_limit: raise _steplimit({where!r}, m)"]
        for statement in compiled:
            lines.extend(self.body_lines(statement))
        fn = self.function([*lines, "return None"])
        fn.inline = lines
        return fn

    def s_assign(self, node):
        target, value_node = node.children
        lines = [f"_v = {self.src(value_node)}", *self.store_lines(target, "_v")]
        return Inline(self, self.guarded(lines, self.where(node)))

    # Types whose coerce() returns a value of this exact Python type unchanged (dialect table).
    COERCE_UNCHANGED: dict[str, str] = {}
    RECORD_TYPES: frozenset = frozenset()  # records of exactly this type pass coerce() unchanged
    LIKE_UNCHANGED: frozenset = frozenset({F32})  # coerce_like(old, new) is new when both have this type

    def coerce_like_source(self, old: str, value: str, where: str) -> str:
        """Source of coerce_like(old, value) (both plain names): value itself when both have one
        type that the dialect stores unchanged."""
        call = f"{self.const(self.coerce_like)}({old}, {value}, {where!r})"
        unchanged = self.const(self.LIKE_UNCHANGED)
        same_record = f"type({old}) is _Record and {value}.type == {old}.type is not None"  # a typed record
        return (
            f"({value} if (_tv := type({value})) is type({old}) and (_tv in {unchanged} or {same_record}) else {call})"
        )

    def coerce_source(self, type_name, value: str, where: str) -> str:
        """Source of coerce(type_name, value): the value itself when it already has the type.
        value is a plain name; where is the source of the location text."""
        if type_name is None:
            return value
        call = f"{self.const(self.coerce)}({self.const(type_name)}, {value}, {where})"
        if isinstance(type_name, str) and type_name in self.COERCE_UNCHANGED:
            return f"({value} if type({value}) is {self.COERCE_UNCHANGED[type_name]} else {call})"
        if isinstance(type_name, str) and type_name in self.RECORD_TYPES:
            return f"({value} if type({value}) is _Record and {value}.type == {type_name!r} else {call})"
        return call

    def assign_target(self, node):
        """The lvalue node of an assignment target (KRL unwraps `whole`)."""
        return node

    def store_lines(self, node, value: str) -> list[str]:
        """Lines that store `value` (a plain name) into a variable, field or element. A field or
        element is stored as a changed copy of its record or array, stored in turn into the one
        holding it, up to the variable. The path is read once, outermost first, so an index
        expression is evaluated once."""
        steps = []  # (kind, key node, node): outermost last
        node = self.assign_target(node)
        while isinstance(node, Tree) and (node.data == "field" or (node.data == "index" and len(node.children) == 2)):
            steps.append((node.data, node.children[1], node))
            node = self.assign_target(node.children[0])
        if not (isinstance(node, Token) or node.data == "var"):
            self.fail(node, f"cannot assign to {node.data}")
        if not steps:
            return self.var_store_lines(node, value)
        steps.reverse()
        lines, keys = [f"_r0 = {self.src(node)}"], []
        for depth, (kind, key_node, step) in enumerate(steps):
            slot, where = f"_r{depth}", repr(self.where(step))
            if kind == "field":
                key = repr(self.norm(str(key_node)))
                lines += [
                    f"if not isinstance({slot}, _Record) or {key} not in {slot}:",
                    f"    _nofield_set({slot}, {str(key_node)!r}, {where})",
                ]
            else:
                key = f"_i{depth}"
                lines += [
                    f"{key} = {self.index_source(key_node)}",
                    f"if not isinstance({slot}, list) or not 0 <= {key} < len({slot}):",
                    f"    _badindex({key} + {self.index_base}, {where})",
                ]
            keys.append(key)
            if depth + 1 < len(steps):
                lines.append(f"_r{depth + 1} = {slot}[{key}]")
        inner = value
        for depth in reversed(range(len(steps))):
            slot, key, (kind, _key_node, step) = f"_r{depth}", keys[depth], steps[depth]
            lines += [
                f"_c = {slot}.shallow()" if kind == "field" else f"_c = list({slot})",
                f"_o = {slot}[{key}]",
                f"_c[{key}] = {self.coerce_like_source('_o', inner, self.where(step))}",
                f"{slot} = _c",
            ]
            inner = slot
        return lines + self.var_store_lines(node, "_r0")

    def var_store_lines(self, node, value: str) -> list[str]:
        """Lines storing value into a variable, as lvalue()'s set_var: the routine's variable,
        else a global, else a new variable (where the language makes one)."""
        token = node if isinstance(node, Token) else node.children[0]
        key = self.norm(str(token))
        where = repr(self.where(token))
        if self.local_types is not None and key in self.local_types:
            return [f"V[{key!r}] = {self.coerce_source(self.local_types[key], value, where)}"]
        if type(self).coerce is Compiler.coerce:  # untyped language: values stored as they are
            local, glob = value, value
        else:
            coerce = self.const(self.coerce)
            local = f"{coerce}(fr.types.get({key!r}), {value}, {where})"
            glob = f"{coerce}(m.global_types.get({key!r}), {value}, {where})"
        return [
            f"if {key!r} in V: V[{key!r}] = {local}",
            f"elif {key!r} in G: G[{key!r}] = {glob}",
            f"else: {self.const(self.new_variable)}(fr, {key!r}, {value}, {where})",
        ]

    def s_halt_stmt(self, node):
        """halt / HALT / Halt: the program stops; its last message is the operator's message."""
        return lambda fr: halt(fr)

    def s_expr_stmt(self, node):
        return Inline(self, self.guarded([self.src(node.children[0])], self.where(node)))

    def s_return_stmt(self, node):
        if node.children and node.children[0] is not None:
            value = self.src(node.children[0])
            return Inline(self, self.guarded([f"return _Signal('return', {value})"], self.where(node)))
        return Inline(self, ["return _Signal('return', None)"])

    def s_break_stmt(self, node):
        return Inline(self, ["return _BREAK"])

    def s_continue_stmt(self, node):
        return Inline(self, ["return _CONTINUE"])

    def s_pass_stmt(self, node):
        return Inline(self, [])

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
        return self.if_chain(branches, else_body, self.where(node))

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

    def if_chain(self, branches, else_body, where: str | None = None) -> Inline:
        """branches: [(condition, body)] as expr() and block() return them; else_body or None."""
        lines = []
        for i, (cond, body) in enumerate(branches):
            lines.append(f"{'if' if i == 0 else 'elif'} {self.source_of(cond)}:")
            lines.extend(indent(self.body_lines(body) or ["pass"]))
        if else_body is not None:
            lines.append("else:")
            lines.extend(indent(self.body_lines(else_body) or ["pass"]))
        return Inline(self, self.guarded(lines, where or self.filename))

    # --- lvalues ----------------------------------------------------------------------------
    def compile_routine_body(self, routine: Routine, statements, local_types: dict | None = None) -> None:
        """local_types: the routine's parameters and declared locals with their types, when the
        language declares them all before the first statement (KRL, RAPID): then the generated
        code reads and stores them directly in the frame."""
        self.local_types, self.routine_name = local_types, routine.name
        try:
            routine.body = self.block(statements)
        finally:
            self.local_types, self.routine_name = None, "module"

    def ref_setters(self, callee: str, arg_nodes) -> list:
        """Setters for arguments that are variables, used if the callee takes them by reference."""
        if self.user_routines is not None and self.norm(callee) not in self.user_routines:
            return [None] * len(arg_nodes)  # a builtin: nothing is written back
        return [
            LazyStore(self, node)
            if isinstance(node, Tree) and node.data in ("var", "index", "field", "whole")
            else None
            for node in arg_nodes
        ]

    def lvalue(self, node):
        """A setter(frame, value) for a variable, an array element or a record field (by-reference
        arguments, loop counters): the lines of store_lines() compiled into a function."""
        lines = self.guarded(self.store_lines(node, "_v"), self.where(node))
        return self.function(lines, "fr, _v", f"{self.name}_{self.routine_name}_store")

    def new_variable(self, fr, key, value, where):
        fr.vars[key] = value

    def coerce_like(self, old, value, where):
        """Store value where old was: keep the slot's number type."""
        if isinstance(old, np.floating) and not isinstance(value, bool):
            try:
                return f32(value)
            except (TypeError, ValueError):
                raise RunError(f"{where}: cannot store {value!r} in a number") from None
        return value


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
    v = value if type(value) is F32 else f32(value)
    if not math.isfinite(v):
        return "nan" if math.isnan(v) else ("inf" if v > 0 else "-inf")
    text = str(v)  # numpy's shortest round-trip digits; positional for 1e-4 <= |v| < 1e16
    if "e" in text:
        return np.format_float_positional(v, trim="-", unique=True)
    return text[:-2] if text.endswith(".0") else text
