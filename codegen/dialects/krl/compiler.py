"""The KRL compiler: REAL in float32, trig in degrees, FRAME/POS with the geometric operator `:`, by module."""

from __future__ import annotations

from lark import Token, Tree

from codegen.dialects import posemath
from codegen.dialects.core.compiler import Compiler
from codegen.dialects.core.machine import pause
from codegen.dialects.core.source import Src
from codegen.dialects.core.values import F32, Record, RunError, Signal, f32, format_general, index_value, op_error
from codegen.dialects.krl import bas, dialogs, eki, io
from codegen.dialects.krl.builtins import BUILTINS, UNINIT, cart, type_name_of, valid, xyzabc
from codegen.dialects.krl.declarations import DECLARATIONS, Declarations
from codegen.dialects.krl.goto import GotoBlocks
from codegen.dialects.krl.interrupts import InterruptStatements
from codegen.dialects.krl.motion import (
    SYSTEM_ARRAY,
    SYSTEM_ARRAYS,
    CircStatement,
    motion_run,
    orientation_store,
    path_variable_store,
    robroot,
    system_inputs,
)
from codegen.dialects.krl.names import Scope, ScopedNames
from codegen.dialects.krl.numbered import fresh_warning
from codegen.dialects.krl.relative import relative_target
from codegen.dialects.krl.signals import SignalGroups
from codegen.dialects.krl.spline import KINDS, WithClauses, motion_parts
from codegen.dialects.krl.state import KRLState
from codegen.dialects.krl.sysvars import set_tool, timers_running
from codegen.dialects.krl.trigger import TriggerStatements

EXIT = frozenset({"exit"})  # the signal kind that ends a KRL loop
NO_SKIP = frozenset()
TIMED = ("$TIMER", "$TIMER_FLAG", "$ROB_TIMER")  # a WAIT FOR on these waits for the clock
CYCLE_S = 0.012  # the interpreter's controller cycle (targets/kuka.toml signal_cycle_s: 12 ms, assumed)
# An aggregate's values are constants: a literal, an enumeration value, a signed number or an aggregate (KSS
# refuses a variable or an expression there when it compiles the module; see targets/kuka.toml, aggregates)
CONSTANT_VALUES = frozenset({"number", "string", "true", "false", "enum", "aggregate"})


def constant_value(node) -> bool:
    """Whether an aggregate's value is a constant (a negative number is one)."""
    while isinstance(node, Tree) and node.data == "neg":
        node = node.children[0]
    return isinstance(node, Tree) and node.data in CONSTANT_VALUES


def operand_error(where: str, exc: Exception) -> RunError:
    """An operator on values it does not take, in KRL's words (Python's message names Python's types)."""
    if isinstance(exc, TypeError):
        return RunError(f"{where}: type mismatch (an operator or an index on values of types it does not take)")
    return op_error(where, exc)


def element(seq, index, offset: int, where: str):
    """seq[index] where the quick path did not take it: an array's element (or a record's component by number)."""
    if not isinstance(seq, list | Record | str):
        raise RunError(f"{where}: {type_name_of(seq)} is not an array")
    return index_value(seq, index, offset, where)


class KRLCompiler(
    ScopedNames,
    Declarations,
    GotoBlocks,
    TriggerStatements,
    WithClauses,
    SignalGroups,
    InterruptStatements,
    CircStatement,
    io.ContinueStatement,
    Compiler,
):
    name = "krl"
    case_insensitive = True
    index_base = 1
    run_state = KRLState
    int_division = True
    halt_resumes = True  # HALT stops the program; the operator's start resumes it at the next statement
    COERCE_UNCHANGED = {"REAL": "_F32", "INT": "int", "BOOL": "bool"}
    INT_RANGE = (-(2**31), 2**31 - 1)  # INT is 32-bit (KRL quick guide, data types): overflow is an error
    LIKE_UNCHANGED = frozenset({F32, int, bool, str})

    def __init__(self, filename: str) -> None:
        super().__init__(filename)
        self.init_types()
        self.scope = Scope("")
        self.signatures: dict[str, list] = {}  # routine key -> its parameters' modes
        self.user_routines = set()
        self.findings: list | None = None  # codegen check: compile errors collected instead of raised
        self.ns.update(_UNINIT=UNINIT, _valid=valid, _operror=operand_error, _index=element)

    # --- tables ------------------------------------------------------------------------------
    def make_builtins(self) -> dict:
        return {**BUILTINS, **bas.FUNCTIONS, **dialogs.BUILTINS, **eki.BUILTINS}

    @staticmethod
    def number(text: str):
        if text.startswith("'"):  # 'Hff' / 'B0101'
            base = 16 if text[1] in "Hh" else 2
            return int(text[2:-1], base)
        if any(c in text for c in ".eE"):
            return f32(float(text))
        return int(text)

    def accepts_input(self, name: str, globals_: dict) -> bool:
        match = SYSTEM_ARRAY.fullmatch(name.upper())
        if match is not None:
            return 1 <= int(match.group(2)) <= SYSTEM_ARRAYS[match.group(1)][1]
        return name.upper() == "$ROBROOT" or super().accepts_input(name, globals_)

    def kept(self, machine, name: str):
        """As the base class; BASE_DATA[n], TOOL_DATA[n], LOAD_DATA[n]: the controller's numbered data (what a
        program wrote into $config.dat, or the value it was given)."""
        match = SYSTEM_ARRAY.fullmatch(name.upper())
        if match is None:
            return super().kept(machine, name)
        values = machine.state.sysvars.get(match.group(1))
        index = int(match.group(2))
        return values[index - 1] if values is not None and 1 <= index <= len(values) else None

    def inject_inputs(self, machine) -> None:
        """BASE_DATA[n]=x,y,z,a,b,c, TOOL_DATA[n]=x,y,z,a,b,c and LOAD_DATA[n]=m,x,y,z[,a,b,c,jx,jy,jz] (mass kg,
        centre of gravity mm, principal axes deg, moments kg m2) set the controller's numbered bases, tools and
        loads, as $config.dat holds them."""
        robroot(machine)
        rest = system_inputs(machine)
        if rest is None:
            return super().inject_inputs(machine)
        original, machine.inputs = machine.inputs, rest
        try:
            super().inject_inputs(machine)
        finally:
            machine.inputs = original

    def stmt(self, node):
        """A statement compiled; for codegen check, a statement that does not compile is a finding and the
        rest goes on."""
        if self.findings is None:
            return super().stmt(node)
        try:
            return super().stmt(node)
        except RunError as exc:
            self.findings.append(exc)
            return self.s_pass_stmt(node)

    # --- expressions -------------------------------------------------------------------------
    def e_enum(self, node):
        return Src(repr("#" + str(node.children[0]).upper()))

    def e_whole(self, node):
        return self.expr(node.children[0])

    def e_row(self, node):
        return self.e_index(Tree("index", node.children, node.meta))

    def e_field(self, node):
        inner = super().e_field(node)
        where, name = self.where(node), str(node.children[1])
        return Src(f"(_u if (_u := {inner}) is not _UNINIT else _valid(_u, {where!r}, {name!r}))")

    @staticmethod
    def nested(node):
        """A[i, j] as A[i][j] (an array of arrays)."""
        base, *indexes = node.children
        for index in indexes:
            base = Tree("index", [base, index], node.meta)
        return base

    def e_index(self, node):
        io_read = io.input_read(self, node)
        if io_read is not None:
            return io_read
        if len(node.children) > 2:
            return self.e_index(self.nested(node))
        inner = super().e_index(node)
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
            if not self.known_type(type_name):
                self.fail(node, f"unknown type {type_name}")
        fields = []
        for item in children:
            name, _brackets, value = item.children
            if not constant_value(value):
                self.fail(
                    value,
                    f"{str(name).upper()} in an aggregate is a variable or an expression: an aggregate takes "
                    "constants only; assign that component on its own (NAME.COMPONENT = value)",
                )
            fields.append(f"{str(name).upper()!r}: {self.src(value)}")
        record = f"_Record(None, {{{', '.join(fields)}}})"
        if type_name is None:
            return Src(record)
        return Src(f"{self.const(self.coerce)}({type_name!r}, {record}, {self.where(node)!r})")

    # --- lvalues and assignment --------------------------------------------------------------
    def coerce_source(self, type_name, value: str, where: str) -> str:
        if isinstance(type_name, tuple):  # an array keeps its elements' own checks (coerce_like)
            return value
        return super().coerce_source(type_name, value, where)

    def coerce_like_source(self, old: str, value: str, where: str) -> str:
        """A component without a value takes the new one as it is (see coerce_like)."""
        return f"({value} if {old} is _UNINIT else {super().coerce_like_source(old, value, where)})"

    def assign_target(self, node):
        while isinstance(node, Tree) and node.data in ("whole", "row"):
            node = node.children[0] if node.data == "whole" else Tree("index", node.children, node.meta)
        if isinstance(node, Tree) and node.data == "index" and len(node.children) > 2:
            return self.nested(node)
        return node

    def coerce_like(self, old, value, where):
        if isinstance(old, Record) and isinstance(value, Record) and value.type is None:
            out = old.shallow()  # a partial aggregate changes only the components it names
            fields = self.struct_fields.get(old.type, {})
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
            fr.m.state.sysvars["$BASE"] = self.coerce("FRAME", value, where)
            return
        if key in SYSTEM_ARRAYS:  # an element was assigned (the array read first, so it is there)
            fr.m.state.sysvars[key] = value
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
        name = str(target_node.children[0]).upper() if is_var else None
        if name in ("$BASE", "$TOOL", "$LOAD"):
            value, where = self.expr(value_node), self.where(node)
            if name == "$BASE":

                def set_base(fr):
                    base = value(fr)
                    fresh_warning(fr.m, base)
                    fr.m.state.sysvars["$BASE"] = self.coerce("FRAME", base, where)

                return set_base
            if name == "$TOOL":
                return lambda fr: set_tool(fr, self.coerce("FRAME", value(fr), where), where)

            def set_load(fr):
                load = value(fr)
                fresh_warning(fr.m, load)
                fr.m.state.sysvars["$LOAD"] = self.coerce("LOAD", load, where)

            return set_load
        declared = self.static_type(target_node)
        if declared is not None:
            self.check_static(value_node, declared, node)
        return super().s_assign(node)

    # --- statements --------------------------------------------------------------------------
    # EXIT leaves LOOP, REPEAT and FOR (from WHILE it is passed on to the loop around).
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

    def s_call_stmt(self, node):
        if str(node.children[0]).upper() == "PULSE":
            return io.pulse(self, node)
        return super().s_call_stmt(node)

    def s_wait_sec(self, node):
        # WAIT SEC stops the advance run: the time runs from the arm's arrival (KSS 8 programming manual)
        seconds, where = self.expr(node.children[0]), self.where(node)

        def run(fr):
            t = float(valid(seconds(fr), where, "WAIT SEC time"))
            if t < 0:  # KSS does not wait (as recalled of the KSS 8 manual's WAIT SEC; the text was not found)
                fr.m.warn(f"{where}: WAIT SEC {format_general(t)}: a negative time does not wait (taken as 0 s)")
                t = 0.0
            fr.m.arrive(where)
            fr.m.elapse(t, where)

        return run

    def s_wait_for(self, node):
        """WAIT FOR stops the advance run; a condition on a timer is waited for cycle by cycle (the clock runs
        while a timer it reads runs), any other until a device makes it true."""
        timed = (
            any(
                isinstance(sub, Tree) and sub.data == "var" and str(sub.children[0]).upper() in TIMED
                for sub in node.children[0].iter_subtrees()
            )
            if isinstance(node.children[0], Tree)
            else False
        )
        if not timed:
            return self.wait_until(node.children[0], node, "WAIT FOR", arrive=True)
        cond, where = self.expr(node.children[0]), self.where(node)

        def run(fr):
            m = fr.m
            m.arrive(where)
            while not cond(fr):
                if not timers_running(m) and m.next_device_time() is None:
                    raise RunError(f"{where}: WAIT FOR a condition that nothing here makes true (waits forever)")
                m.wait_for(lambda: cond(fr), where, CYCLE_S, "WAIT FOR")

        return run

    def s_halt_stmt(self, node):
        where = self.where(node)

        def run(fr):  # HALT stops the advance run: the arm stops at the end of its move
            fr.m.arrive(where)
            pause(fr)

        return run

    def s_brake_stmt(self, node):
        self.fail(node, "BRAKE (in an interrupt routine) is not modelled by this interpreter")

    def s_analog_stmt(self, node):
        what = f"{node.children[0]} {node.children[1]}"
        self.fail(node, f"{what} (cyclic analog I/O) is not modelled by this interpreter")

    def s_on_error_stmt(self, node):
        self.fail(node, "ON_ERROR_PROCEED (error handling, $ERR) is not modelled by this interpreter")

    def s_resume_stmt(self, node):
        self.fail(node, "RESUME (in an interrupt routine) is not modelled by this interpreter")

    def s_motion_stmt(self, node):
        reference = next((c for c in node.children if isinstance(c, Tree) and c.data == "reference"), None)
        rest, approx, with_clause = motion_parts([c for c in node.children if c is not reference])
        motion, target = rest
        keyword = str(motion).upper()
        static = {"approx": str(approx).upper() if approx is not None else None}
        value, where, line = self.expr(target), self.where(node), self.line(node)
        if keyword.endswith("_REL"):
            value = relative_target(value, "#" + str(reference.children[0]).upper() if reference else "#BASE", where)
            keyword = keyword[: -len("_REL")]
        elif reference is not None:
            self.fail(reference, f"{keyword} ... #{reference.children[0]}: only a relative motion has one")
        run = motion_run(self, KINDS[keyword], static, value, where, line)
        return self.around(self.with_statements(with_clause) if with_clause is not None else [], run)

    def s_circ_stmt(self, node):
        rest, approx, with_clause = motion_parts(node.children)
        self.refuse_relative(node, str(rest[0]).upper())
        plain = Tree("circ_stmt", [*rest, approx], node.meta)
        run = super().s_circ_stmt(plain)
        return self.around(self.with_statements(with_clause) if with_clause is not None else [], run)

    def s_ext_routine(self, node):
        self.fail(node, "EXT after the first statement of a routine (KRL: declarations come first)")

    s_ext_function = s_ext_routine

    def s_interrupt_decl(self, node):
        """The handler by its key in this module's scope (a module's own routine, or a global one)."""
        children = list(node.children)
        key = self.scope.routines.get(str(children[3]).upper())
        if key is not None:
            children[3] = Token("NAME", key, line=children[3].line, column=children[3].column)
        return super().s_interrupt_decl(Tree(node.data, children, node.meta))

    # --- routines ----------------------------------------------------------------------------
    def routine(self, node, key: str) -> None:
        returns = node.data == "def_function"
        type_token, name, param_parts, body = self.routine_parts(node.children[1:], returns)
        params = [
            (str(pname).upper(), str(mode).upper() if mode is not None else "IN", None)
            for pname, _brackets, mode in param_parts
        ]
        decls, statements, seen = [], [], {}
        for child in body.children:
            if not isinstance(child, Tree):
                continue
            if child.data in DECLARATIONS:
                if statements:
                    self.fail(child, "a declaration after the first statement (KRL: declarations come first)")
                if child.data == "decl":
                    self.declared_once(child, seen)
                    decls.extend(self.decl_items(child))
                elif child.data == "signal_decl":
                    self.s_signal_decl(child)
                elif child.data == "import_decl":
                    self.s_import_decl(child)
            else:
                statements.append(child)
        declared = {d[0]: d[1] for d in decls}  # parameters are typed by their DECL lines
        params = [(p, m, declared.get(p)) for p, m, _ in params]
        local_decls = [d for d in decls if d[0] not in {p for p, _, _ in params}]
        return_type = str(type_token).upper() if type_token else None
        if return_type is not None and not self.known_type(return_type):
            self.fail(type_token, f"unknown type {type_token}")
        self.define_routine(key, name, params, return_type, node, statements, local_decls, declared)

    def check_params(self, node, name, params) -> None:
        for pname, _m, ptype in params:
            if ptype is None:
                self.fail(node, f"parameter {pname} of {name} has no DECL")
