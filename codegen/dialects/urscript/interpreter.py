"""URScript interpreter: float32 numbers, radians, poses in metres with rotation vectors."""

# The language as the URScript manual (The URScript Programming Language, e-Series SW 5.x) defines it:
# - Function: `def f(a, b=1): ... end`; a call gives the arguments in order, may leave out those with a
#   default value and may name them (`f(1, b=2)`); arguments are passed by value.
# - Scoping rules: a variable assigned in a function is the function's own unless a global of that name
#   exists; `global x [= value]` makes x the program's, `local x [= value]` the function's even where a
#   global x exists. The program's own body (the outermost `def`) holds the globals.
# - Program Label: PolyScope's `$ n "text"` lines only mark where the program is: no effect.
# - Threads (threads.py); an expression goes on over lines inside (), [] and p[] (Brackets below: the manual's
#   examples write long lists over lines, as Python does; assumed: the manual has no chapter on line breaks).
# - A call of a function that neither the program nor this interpreter defines is refused when the program is
#   loaded, naming its file:line: a built-in of the script directory not modelled with the reason
#   (environment.py NOT_MODELLED), any other name as not defined.
# - Installation variables (PolyScope manual, Variables: "can be used by multiple programs and their names and
#   values are persisted together with the robot installation"): a PolyScope program's preamble defines each as a
#   global before the program's own lines (`global i_var_1=p[...]` beside set_tcp and the other installation
#   settings: assumed from programs PolyScope generated, the manuals at hand do not print the preamble). A run is
#   given them as inputs named installation.NAME (INSTALLATION): each a global before the program starts, unless
#   the program's own set-up assigns the name (its lines run after the preamble). A name read that neither the
#   program nor the installation defines stops the run with an error naming it (the controller refuses it too:
#   "Compile error: name '...' is not defined", as users report; the manuals at hand do not describe the error).

from __future__ import annotations

import re

from lark import Token, Tree

from codegen.dialects.core.compiler import Compiler
from codegen.dialects.core.machine import halt
from codegen.dialects.core.parsing import parse_with_grammar
from codegen.dialects.core.program import Program
from codegen.dialects.core.source import Src
from codegen.dialects.core.values import MISSING, RunError, f32
from codegen.dialects.urscript import (
    arrays,
    circle,
    conveyor,
    environment,
    io,
    motion,
    pendant,
    secondary,
    threads,
    urmath,
)
from codegen.dialects.urscript.state import URScriptState
from codegen.dialects.urscript.values import INT_RANGE, URPose, int_overflow, num, pose

INPUT_REGISTER = re.compile(r"(?:input|output)_(?:integer|float|boolean)_register_(\d+)")
REGISTER_MAX = io.REGISTER_MAX
INSTALLATION = "installation."  # an input installation.NAME: the installation variable NAME (a global at the start)
IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
ROUTINES = ("funcdef", "secdef")  # the definitions a call can name
POSE_SIZE = 6  # six numbers given for an installation variable: a pose p[x, y, z, rx, ry, rz] (m, rad)


class Brackets:
    """Lark postlex: a line end inside (), [] or p[] does not end the statement (the expression goes on)."""

    always_accept = ("_NL",)
    OPEN = frozenset({"LPAR", "LSQB", "POSE_OPEN"})
    CLOSE = frozenset({"RPAR", "RSQB"})

    def process(self, stream):
        depth = 0
        for token in stream:
            kind = token.type
            if kind in self.OPEN:
                depth += 1
            elif kind in self.CLOSE:
                depth = max(0, depth - 1)
            elif kind == "_NL" and depth:
                continue
            yield token


BRACKETS = Brackets()


def parse(text: str, filename: str = "<urscript>", positions: bool = True) -> Tree:
    return parse_with_grammar(__file__, text, filename, positions, postlex=BRACKETS)


class URScriptCompiler(threads.ThreadStatements, Compiler):
    name = "urscript"
    index_base = 0
    run_state = URScriptState
    BIND_ARGUMENTS = True  # named arguments and default values (Function)
    INT_RANGE = INT_RANGE  # a literal, a sum, difference, product or negation past it is refused (values.py)

    def __init__(self, filename: str) -> None:
        super().__init__(filename)
        self.threads: dict = {}  # thread definitions by name (codegen/dialects/urscript/threads.py)
        self.thread_runs: list[tuple[str, object]] = []  # (name, node) of each `run name()`, checked by load()
        self.defined: set[str] = set()  # every function and thread the program defines (known before compiling)
        self.function_nodes: dict = {}  # each `def` and `sec` by name (a secondary program's calls are checked)
        self.global_names: set[str] = set()  # names a `global` statement makes the program's
        self.thread_names: set[str] = set()  # every thread the program defines
        self.never_lists: arrays.NeverLists | None = None  # which expressions are never arrays (set by load)

    def make_builtins(self) -> dict:
        return {
            **urmath.builtins(),
            **io.builtins(),
            **motion.builtins(),
            **environment.builtins(),
            **conveyor.builtins(pose, num),
            **pendant.builtins(),
            "movec": circle.builtin(pose, num, threads.current),
            "halt": halt,
        }

    # --- registers by name, for devices: input_* and output_* are the controller's registers ------
    def accepts_input(self, name: str, globals_: dict) -> bool:
        """Input registers (input_integer_register_24, ...) are read by index at run time; installation.NAME is
        an installation variable (any name: the installation may hold variables the program does not use)."""
        if name.startswith(INSTALLATION):
            return IDENTIFIER.fullmatch(name[len(INSTALLATION) :]) is not None
        match = INPUT_REGISTER.fullmatch(name)
        return (match is not None and int(match.group(1)) <= REGISTER_MAX) or super().accepts_input(name, globals_)

    def inject_inputs(self, machine) -> None:
        """The installation's variables first (the preamble's globals), then the inputs that are the program's."""
        for name, value in machine.inputs.items():
            if name.startswith(INSTALLATION):
                key = name[len(INSTALLATION) :]
                if key not in machine.globals:  # the program's own set-up assigns it after the preamble
                    machine.globals[key] = installation_value(value, name)
        super().inject_inputs(machine)

    def var_reader(self, token):
        """A name neither the program nor the installation defines: an error naming both."""
        name, where = str(token), self.where(token)

        def read(fr):
            value = fr.vars.get(name, MISSING)
            if value is MISSING:
                value = fr.m.globals.get(name, MISSING)
                if value is MISSING:
                    raise RunError(
                        f"{where}: undefined variable {name}: neither the program's nor the installation's "
                        f"(a run is given an installation variable as {INSTALLATION}{name})"
                    )
            return value

        return read

    def device_read(self, machine, name: str):
        if name.startswith("input_"):
            return machine.inputs.get(name, 0)
        if name.startswith("output_"):  # what the program wrote, else what the register held at the start
            return machine.outputs.get(name, machine.inputs.get(name, 0))
        return super().device_read(machine, name)

    def device_write(self, machine, name: str, value) -> bool:
        if name.startswith("input_"):
            machine.inputs[name] = value
            return True
        return super().device_write(machine, name, value)

    # --- arithmetic: numbers inline, arrays element-wise (arrays.py) ----------------------------
    def _arithmetic(self, node, symbol: str, scalar: str | None = None) -> Src:
        """a <symbol> b inline where neither is an array, else arrays.py (element-wise); an operand the program
        never makes an array (arrays.NeverLists) is not tested. scalar: the numbers' form where it is a call
        (division), else the operator inline. The operands are evaluated once, left first."""
        left_node, right_node = node.children
        left, right = self.src(left_node), self.src(right_node)
        never = self.never_lists.never if self.never_lists is not None else (lambda n: False)
        left_plain, right_plain = never(left_node), never(right_node)
        a, b = self.temp(), self.temp()
        if left_plain and right_plain:
            return Src(f"({left} {symbol} {right})" if scalar is None else f"{scalar}({left}, {right})")
        slow = f"{self.const(arrays.operation(symbol))}({a}, {b}, {self.where(node)!r})"
        fast = f"({a} {symbol} {b})" if scalar is None else f"{scalar}({a}, {b})"
        if right_plain:  # the right operand is evaluated after the left one's test, in either branch
            fast, slow = fast.replace(b, f"({right})"), slow.replace(f", {b},", f", ({right}),")
            return Src(f"({fast} if type({a} := {left}) is not list else {slow})")
        return Src(f"({fast} if (type({a} := {left}) is not list) & (type({b} := {right}) is not list) else {slow})")

    def _int_checked(self, node, symbol: str) -> Src:
        """The arithmetic with an int result checked against the controller's 32-bit ints (a float passes)."""
        r, (low, high) = self.temp(), self.INT_RANGE
        what = "the negation" if symbol == "neg" else f"the {symbol}"
        refuse = f"{self.const(int_overflow)}({r}, {what!r}, {self.where(node)!r})"
        value = self._arithmetic(node, symbol) if symbol != "neg" else super().e_neg(node)
        return Src(f"({r} if type({r} := {value}) is not int or {low} <= {r} <= {high} else {refuse})")

    def e_neg(self, node):
        return self._int_checked(node, "neg")

    def e_add(self, node):
        return self._int_checked(node, "+")

    def e_sub(self, node):
        return self._int_checked(node, "-")

    def e_mul(self, node):
        return self._int_checked(node, "*")

    def e_div(self, node):
        return self._arithmetic(node, "/", self.const(self.divide))

    # --- rules beyond the common ones ---------------------------------------------------------
    def e_pose_lit(self, node):
        parts = [self.expr(c) for c in node.children[1:]]
        where = self.where(node)
        if len(parts) != 6:
            self.fail(node, f"a pose has 6 numbers, got {len(parts)}")

        def make(fr):
            return URPose([num(p(fr), where, "pose component") for p in parts])

        return make

    def e_list_lit(self, node):
        parts = [self.expr(c) for c in node.children if c is not None]
        return lambda fr: [p(fr) for p in parts]

    def e_call(self, node):
        callee, args_node = node.children
        if isinstance(callee, Tree) and callee.data == "field":  # conn.method(): an object rpc_factory made
            self.fail(node, f"{_dotted(callee)}() is not modelled: objects with methods (XML-RPC, fieldbus) are not")
        if not (isinstance(callee, Tree) and callee.data == "var"):
            self.fail(node, "only named functions can be called")
        name = str(callee.children[0])
        self.check_callee(name, callee.children[0])
        positional, named = [], {}
        for arg in args_node.children if args_node is not None else []:
            if isinstance(arg, Tree) and arg.data == "kwarg":
                named[str(arg.children[0])] = self.src(arg.children[1])
            else:
                positional.append(self.src(arg))
        return self.call_source(name, positional, named, None, self.where(node))

    def check_callee(self, name: str, token) -> None:
        """A function the program defines or a built-in this interpreter models; else refused now, at load."""
        if name in self.defined or name in self.builtins:
            return
        if name in self.thread_names:
            self.fail(token, f"{name} is a thread: start it with run {name}()")
        reason = environment.NOT_MODELLED.get(name)
        if reason is not None:
            self.fail(token, f"{name} is not modelled: {reason}")
        self.fail(token, f"{name} {environment.UNDEFINED}")

    def s_global_stmt(self, node):
        key, value_node = str(node.children[0]), node.children[1]
        self.global_names.add(key)
        if value_node is None:  # `global x`: the name is the program's from here on
            return lambda fr: None
        value = self.expr(value_node)

        def run(fr):
            fr.m.globals[key] = value(fr)

        return run

    def s_local_stmt(self, node):
        key, value_node = str(node.children[0]), node.children[1]
        value = self.expr(value_node) if value_node is not None else (lambda fr: None)

        def run(fr):
            fr.vars[key] = value(fr)

        return run

    def var_store_lines(self, node, value: str) -> list[str]:
        """A name declared global before (a `global x` above, in source order): stored as the program's
        variable, also where it does not exist yet; any other as the core stores it."""
        token = node if isinstance(node, Token) else node.children[0]
        key = str(token)
        if key in self.global_names and not (self.local_types is not None and key in self.local_types):
            return [f"if {key!r} in V and V is not G: V[{key!r}] = {value}", f"else: G[{key!r}] = {value}"]
        return super().var_store_lines(node, value)

    def s_label_stmt(self, node):
        return lambda fr: None  # `$ 3 "MoveJ"`: PolyScope's mark of the program node (Program Label)

    def s_critical_stmt(self, node):
        return lambda fr: None  # one thread runs at a time here: nothing interleaves with a critical section

    def s_secdef(self, node):
        return self.s_funcdef(node)  # load() has refused what a secondary program may not hold (secondary.py)

    def s_funcdef(self, node):
        name_token, params_node, body = node.children
        if str(name_token) in self.threads:
            self.fail(name_token, f"{name_token} is defined as a thread already")
        params, defaults = [], {}
        for param in params_node.children if params_node is not None else []:
            pname, default = str(param.children[0]), param.children[1]
            params.append((pname, "IN", None))
            if default is not None:
                defaults[pname] = self.expr(default)
        self.define_routine(
            str(name_token), name_token, params, None, node, body.children, unique=False, defaults=defaults
        )
        return lambda fr: None  # defined at compile time


def installation_value(value, name: str):
    """An installation variable's value as the program sees it: six numbers a pose (the installation variables
    of a TCP or a feature), other numbers a list, a number, a bool or a string as it is."""
    if isinstance(value, URPose | bool | str | int | float):
        return f32(value) if type(value) is float else value
    if isinstance(value, tuple | list) and all(isinstance(v, int | float) and not isinstance(v, bool) for v in value):
        return URPose(value) if len(value) == POSE_SIZE else [f32(v) for v in value]
    raise RunError(f"{name}: an installation variable is a number, a bool, a string, a list or a pose")


def _dotted(node) -> str:
    """a.b.c of a field access."""
    if isinstance(node, Tree) and node.data == "field":
        return f"{_dotted(node.children[0])}.{node.children[1]}"
    if isinstance(node, Tree) and node.data == "var":
        return str(node.children[0])
    return "..."


def _is_constant(node) -> bool:
    """Literals only (numbers, strings, lists, pose literals): safe to evaluate once."""
    if isinstance(node, Token):
        return node.type in ("NUMBER", "STRING", "POSE_OPEN")
    if node.data in ("call", "var"):
        return False
    return all(_is_constant(c) for c in node.children if c is not None)


def load(text: str, filename: str = "<urscript>") -> Program:
    """Parse and compile; the outermost `def` is the program, its variables are the globals.

    Its leading constant assignments and function definitions run once, when the program is loaded (an
    error there is the program's, reported once); the rest on every run.
    """
    tree = parse(text, filename)
    compiler = URScriptCompiler(filename)
    routines = [d for d in tree.iter_subtrees_topdown() if d.data in ROUTINES]
    compiler.function_nodes = {str(d.children[0]): d for d in routines}
    compiler.defined = set(compiler.function_nodes)
    for sec in tree.find_data("secdef"):
        found = secondary.refusal(sec, compiler.function_nodes)
        if found is not None:
            compiler.fail(*found)
    compiler.user_routines = set(compiler.defined)
    thread_names = {str(d.children[0]) for d in tree.find_data("threaddef")}
    compiler.thread_names = thread_names
    compiler.never_lists = arrays.NeverLists(tree, compiler.builtins, compiler.defined)
    top = [c for c in tree.children if isinstance(c, Tree)]
    programs = [c for c in top if c.data in ROUTINES]  # a `def`, or a `sec`: a secondary program (secondary.py)
    if len(top) == 1 and len(programs) == 1:
        statements = [c for c in programs[0].children[2].children if isinstance(c, Tree)]
        name = str(programs[0].children[0])
    else:
        statements, name = top, filename
    split = 0
    while split < len(statements) and (
        statements[split].data in ("funcdef", "secdef", "threaddef", "label_stmt")
        or (statements[split].data == "assign" and _is_constant(statements[split].children[1]))
    ):
        split += 1
    prefix_statements = []
    for statement in statements[:split]:
        prefix_statements.append(compiler.stmt(statement))

    def prefix(fr):
        for statement in prefix_statements:
            statement(fr)

    rest = compiler.block(statements[split:])

    def body(fr):
        signal = rest(fr)
        motion.settle(fr, filename)  # a speedl / speedj under way stops with the program
        return signal

    compiler.check_thread_runs()
    if len(top) == 1 and top[0].data == "secdef":
        body = secondary.one_step(name, body)
    program = Program(name, compiler, prefix, None, threads.ending_threads(body))
    program.prepare()
    return program
