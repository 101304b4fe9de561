"""`codegen check` of URScript: syntax, unsupported and undefined names, and the field's checks (waits, TCP, speeds)."""

# What it reports, each with file:line:column:
# - syntax errors (every file); a call of a function neither the program nor the interpreter defines ("error",
#   undefined-function), or of a built-in not modelled ("unsupported", with why: environment.py): all of them,
#   not only the first; a variable read but assigned, declared or a parameter nowhere in the program ("error",
#   undefined-name); then whatever else loading refuses (a pose of 5 numbers, a thread with parameters ...).
# - wait-without-timeout ("warning"): `while not get_standard_digital_in(0): sync() end` and its kin: a loop
#   whose condition reads an input (digital, analog, a register, a flag) and whose body only waits (sync,
#   sleep) and counts nothing: the program hangs for ever if the input never comes (a loop that also ends on a
#   second input, an operator's stop, is not reported).
# - motion-before-tcp ("warning"): a move (movej, movel, movep, movec, speedl, speedj, servoj) the program
#   makes before its first set_tcp, in program order (a function's body where it is called): the arm moves
#   with whatever TCP the installation holds.
# - speed-over-arm ("warning"): a joint speed the program states as a number (movej's and servoj's v, rad/s of
#   the leading axis; speedj's qd per axis) over the arm's fastest joint (--robot; without it, over the
#   fastest joint of any e-Series arm). The arms' joint speeds: UR e-Series user manuals, technical
#   specifications (UR3e base, shoulder, elbow 180 deg/s, wrists 360 deg/s; UR5e 180 deg/s; UR10e and UR16e
#   base and shoulder 120 deg/s, the others 180 deg/s): not confirmed in the manuals at hand. TCP speeds are
#   not checked: their limit is the installation's safety setting, which the program does not state.
# - what run stops on, found before it runs ("error"): a call of the program's own function with too many or too
#   few arguments or a keyword it has no parameter for (arity); a list variable (every assignment of its name a
#   list literal) indexed by a literal beyond the longest of them (index). And ("warning", read-before-assign) a
#   variable read in a function (or the program) before the first statement there that assigns it, where nothing
#   else in the program assigns it, no `global` names it (an installation's variable may) and no loop holds both:
#   run stops at the read (undefined variable).
# - overflow ("error"): a number literal, or a sum, difference, product or negation of literals, past the
#   controller's 32-bit ints (values.INT_RANGE) or its float32 numbers: run refuses the literal when it loads the
#   program and stops at the arithmetic (each one is reported, not only the first).
# - runaway-loop ("error"): `while True:` (or a nonzero number) whose body, and the program's functions it calls,
#   takes no physical time (no move, sync, sleep: PHYSICAL_TIME; no join, no operator's or client's answer) and
#   has no break, return or halt. URScript manual (e-Series SW 5.25, Thread scheduling, STATED): a thread that
#   uses its 2 ms slice by "computational heavy instructions (such as an infinite loop that do not control the
#   robot)" should hold a sync or sleep, "otherwise an exception like 'Lost communication with Controller' can be
#   raised with a consequent protective stop". Run stops such a loop at its step limit.

from __future__ import annotations

import math
import operator

from lark import Token, Tree

from codegen.dialects.core.files import Finding, finding_of
from codegen.dialects.core.literals import literal_number as _number
from codegen.dialects.core.values import F32_MAX, RunError
from codegen.dialects.urscript import environment
from codegen.dialects.urscript.values import INT_RANGE

JOINT_SPEED_DEG_S = {
    "UR3e": (180.0, 180.0, 180.0, 360.0, 360.0, 360.0),
    "UR5e": (180.0,) * 6,
    "UR10e": (120.0, 120.0, 180.0, 180.0, 180.0, 180.0),
    "UR16e": (120.0, 120.0, 180.0, 180.0, 180.0, 180.0),
}
FAMILY_MAX_DEG_S = max(max(v) for v in JOINT_SPEED_DEG_S.values())
MOTION = ("movej", "movel", "movep", "movec", "speedl", "speedj", "servoj")
WAIT_BODY = ("sync", "sleep")  # what a bare wait loop does in its body
PHYSICAL_TIME = frozenset((*MOTION, "servoc", "stopj", "stopl", *WAIT_BODY))  # the calls that take physical time
WAITS_FOR_ANSWER = ("popup", "request_")  # calls that may wait for an operator or a client (names or their start)
LOOP_EXITS = ("break_stmt", "return_stmt", "halt_stmt", "join_stmt")  # a loop's ends, and a wait for a thread
INPUT_READS = ("_digital_in", "_analog_in", "read_input_", "get_flag")  # what a device or a peer sets


def _line(node) -> tuple[int, int]:
    meta = getattr(node, "meta", None)
    if isinstance(node, Token):
        return node.line or 0, node.column or 0
    if meta is not None and not meta.empty:
        return meta.line, meta.column
    return 0, 0


def _calls(node):
    """Every call in a subtree: (name, call node)."""
    for call in node.find_data("call"):
        callee = call.children[0]
        if isinstance(callee, Tree) and callee.data == "var":
            yield str(callee.children[0]), call


_DEFINITIONS = ("funcdef", "threaddef", "secdef")
_OPERATIONS = {"add": operator.add, "sub": operator.sub, "mul": operator.mul}
_SYMBOLS = {"add": "+", "sub": "-", "mul": "*"}


def _own_nodes(statements):
    """Every node of a scope's statements, not those of a function or thread defined in them (their own scope)."""
    stack = [s for s in reversed(list(statements)) if isinstance(s, Tree)]
    while stack:
        node = stack.pop()
        if node.data in _DEFINITIONS:
            continue
        yield node
        stack.extend(c for c in reversed(node.children) if isinstance(c, Tree))


def _assigned(node) -> str | None:
    """The variable an assignment sets as a whole (x = ...), None for an element or a field (x[1] = ...)."""
    target = node.children[0]
    return str(target.children[0]) if isinstance(target, Tree) and target.data == "var" else None


def _list_length(value) -> int | None:
    """A list literal's length, None for any other value."""
    if isinstance(value, Tree) and value.data == "list_lit":
        return sum(1 for c in value.children if c is not None)
    return None


def _last_line(node) -> int:
    return max((t.line for t in node.scan_values(lambda v: isinstance(v, Token)) if t.line), default=0)


def _holds(node, at: tuple[int, int]) -> bool:
    """Whether a position lies within a statement (an assignment reading its own variable: x = x + 1)."""
    return _line(node) <= at and at[0] <= _last_line(node)


class Checker:
    """The static checks of one program file's tree (the builtins: the interpreter's table)."""

    def __init__(self, tree: Tree, filename: str, builtins: dict, arm=None) -> None:
        self.tree, self.filename, self.builtins = tree, filename, builtins
        self.findings: list[Finding] = []
        self.folded: dict[int, object] = {}  # id of an expression -> its value (None: not a constant, or reported)
        self.functions = {str(d.children[0]): d for d in tree.find_data("funcdef")}
        self.threads = {str(d.children[0]): d for d in tree.find_data("threaddef")}
        limits = JOINT_SPEED_DEG_S.get(getattr(arm, "model", None) or "")
        self.joint_max_deg_s = limits if limits is not None else (FAMILY_MAX_DEG_S,) * 6
        self.arm_name = getattr(arm, "model", None) if limits is not None else "any e-Series arm"

    def add(self, node, severity: str, code: str, message: str) -> None:
        line, column = _line(node)
        self.findings.append(Finding(self.filename, line, column, severity, code, message))

    def run(self) -> list[Finding]:
        self.callees()
        self.undefined_names()
        self.waits()
        self.motion_before_tcp()
        self.speeds()
        self.arity()
        self.list_indexes()
        self.reads_before_assign()
        self.overflows()
        self.runaway_loops()
        return self.findings

    # --- numbers past the controller's ----------------------------------------------------------
    def overflows(self) -> None:
        """Each literal, and each sum, difference, product or negation of literals, past the controller's
        numbers: the innermost such expression of each."""
        for node in self.tree.iter_subtrees_topdown():  # an expression before its operands: -2147483648 is an int
            if node.data in ("number", "neg", "add", "sub", "mul"):
                self.fold(node)

    def fold(self, node, negated: bool = False):
        """The value of a constant expression, as run computes it (ints exact, floats past float32 refused); None
        for any other expression, and for one past the controller's numbers (reported here, once). negated: the
        literal is the operand of a minus sign (-2147483648 is an int)."""
        if id(node) in self.folded:
            return self.folded[id(node)]
        value, problem, low, high = None, None, *INT_RANGE
        if node.data == "number":
            text = str(node.children[0])
            shown = text if len(text) <= 20 else text[:20] + "..."
            try:
                value = int(text) if text.isdigit() else float(text)
            except ValueError:
                problem = f"number {shown} has more digits than a controller reads"
            if isinstance(value, int) and value > (-low if negated else high):
                problem = f"number {shown} is beyond the controller's integers ({low}..{high}, 32-bit)"
        elif node.data in ("neg", "add", "sub", "mul"):
            children = [c for c in node.children if isinstance(c, Tree)]
            literal = node.data == "neg" and children[0].data == "number"
            operands = [self.fold(c, negated=literal) for c in children]
            if len(operands) == len(node.children) and all(v is not None for v in operands):
                value = -operands[0] if node.data == "neg" else _OPERATIONS[node.data](*operands)
                what = "negation" if node.data == "neg" else _SYMBOLS[node.data]
                if isinstance(value, int) and not low <= value <= high:
                    problem = f"integer overflow: the {what} gives {value}, beyond the controller's 32-bit ints"
        if isinstance(value, float) and not abs(value) <= F32_MAX:
            shown = f"number {shown}" if node.data == "number" else f"the {what} gives {value:.7g}, which"
            limit = f"32-bit floating point: at most {F32_MAX:.7g}"
            problem = problem or f"{shown} is beyond the controller's numbers ({limit})"
        if problem is not None:
            self.add(node, "error", "overflow", problem)
            value = None
        self.folded[id(node)] = value
        return value

    # --- loops that never end and take no time ---------------------------------------------------
    def runaway_loops(self) -> None:
        for loop in self.tree.find_data("while_stmt"):
            condition, body = loop.children
            always = condition.data == "true" or (condition.data == "number" and _number(condition) not in (0, None))
            if isinstance(condition, Tree) and always and not self.ends_or_waits(body, set()):
                message = "the loop never ends and takes no physical time (no move, sync or sleep): the controller "
                message += "stops the program (protective stop); put a sync() in it"
                self.add(loop, "error", "runaway-loop", message)

    def ends_or_waits(self, body, entered: set) -> bool:
        """Whether statements (and the program's functions they call, at any depth) may end a loop or take time."""
        for node in _own_nodes(body.children):
            if node.data in LOOP_EXITS:
                return True
        for name, _call in _calls(Tree("body", list(_own_nodes(body.children)))):
            if name in PHYSICAL_TIME or name == "halt" or name.startswith(WAITS_FOR_ANSWER):
                return True
            if name in self.functions and name not in entered:
                entered.add(name)
                if self.ends_or_waits(self.functions[name].children[2], entered):
                    return True
            elif name not in self.functions and name not in self.builtins:
                return True  # not known: reported as such, not judged here
        return False

    # --- names ----------------------------------------------------------------------------------
    def callees(self) -> None:
        for call in self.tree.find_data("call"):
            if isinstance(call.children[0], Tree) and call.children[0].data == "field":
                self.add(call, "unsupported", "unsupported", "a method of an object (XML-RPC, fieldbus): not modelled")
        for name, call in _calls(self.tree):
            if name in self.functions or name in self.builtins:
                continue
            token = call.children[0].children[0]
            if name in self.threads:
                self.add(token, "error", "thread-called", f"{name} is a thread: start it with run {name}()")
            elif name in environment.NOT_MODELLED:
                reason = environment.NOT_MODELLED[name]
                self.add(token, "unsupported", "unsupported", f"{name} is not modelled: {reason}")
            else:
                self.add(token, "error", "undefined-function", f"{name} {environment.UNDEFINED}")

    def undefined_names(self) -> None:
        assigned = set(self.functions) | set(self.threads)
        for node in self.tree.iter_subtrees():
            if node.data in ("global_stmt", "local_stmt") or node.data == "param":
                assigned.add(str(node.children[0]))
            elif node.data == "assign":
                target = node.children[0]
                while isinstance(target, Tree) and target.data in ("index", "field"):
                    target = target.children[0]
                if isinstance(target, Tree) and target.data == "var":
                    assigned.add(str(target.children[0]))
        called = {id(call.children[0]) for _name, call in _calls(self.tree)}
        reported = set()
        for node in self.tree.find_data("var"):
            name = str(node.children[0])
            if id(node) in called or name in assigned or name in reported:
                continue
            reported.add(name)
            self.add(node, "error", "undefined-name", f"{name} is read but never assigned in the program")

    # --- what run stops on -----------------------------------------------------------------------
    def arity(self) -> None:
        """Calls of the program's own functions: each parameter without a default given, no more arguments than
        parameters, no keyword that is not a parameter (the interpreter's builtins are not in the program)."""
        for name, call in _calls(self.tree):
            definition = self.functions.get(name)
            if definition is None:
                continue
            params = definition.children[1].children if definition.children[1] is not None else []
            names = [str(p.children[0]) for p in params]
            required = [str(p.children[0]) for p in params if p.children[1] is None]
            args = call.children[1].children if call.children[1] is not None else []
            positional = [a for a in args if not (isinstance(a, Tree) and a.data == "kwarg")]
            named = [str(a.children[0]) for a in args if isinstance(a, Tree) and a.data == "kwarg"]
            given = set(names[: len(positional)]) | set(named)
            unknown = [k for k in named if k not in names]
            twice = [k for i, k in enumerate(named) if k in names[: len(positional)] or k in named[:i]]
            missing = [p for p in required if p not in given]
            if len(positional) > len(names):
                problem = f"{name} takes {len(names)} arguments, got {len(positional)}"
            elif unknown:
                problem = f"{name} has no parameter {unknown[0]}"
            elif twice:
                problem = f"{name}: argument {twice[0]} given twice"
            elif missing:
                problem = f"{name}: no value for its parameter {missing[0]} (and it has no default)"
            else:
                continue
            self.add(call, "error", "arity", problem)

    def list_lengths(self) -> dict[str, int]:
        """The variables every assignment of whose name (anywhere in the program) is a list literal, and that no
        function takes as a parameter: the longest of those lists (an index beyond it is beyond each)."""
        lengths: dict[str, set] = {}
        for node in self.tree.iter_subtrees():
            if node.data == "param":
                lengths.setdefault(str(node.children[0]), set()).add(None)
            elif node.data in ("global_stmt", "local_stmt"):
                lengths.setdefault(str(node.children[0]), set()).add(_list_length(node.children[1]))
            elif node.data == "assign" and isinstance(node.children[0], Tree) and node.children[0].data == "var":
                lengths.setdefault(str(node.children[0].children[0]), set()).add(_list_length(node.children[1]))
        return {name: max(sizes) for name, sizes in lengths.items() if None not in sizes}

    def list_indexes(self) -> None:
        """A literal index beyond every list a variable is assigned (URScript lists run from 0)."""
        lengths = self.list_lengths()
        for node in self.tree.find_data("index"):
            base, at = node.children[0], _number(node.children[1])
            if not (isinstance(base, Tree) and base.data == "var") or at is None or at != int(at):
                continue
            size = lengths.get(str(base.children[0]))
            if size is not None and not 0 <= at < size:
                message = f"index {int(at)} out of range: {base.children[0]} is assigned lists of at most {size}"
                self.add(node, "error", "index", message)

    def reads_before_assign(self) -> None:
        """A variable read in a scope (a function's body, or the program's) before the first statement of that scope
        that assigns it, where nothing else in the program assigns it, no `global` names it and no loop holds both
        the read and an assignment: run stops at the read (undefined variable)."""
        scopes = [c for c in self.tree.children if isinstance(c, Tree) and c.data not in _DEFINITIONS]
        scopes = [(None, scopes)] + [
            (d, d.children[2].children) for d in self.tree.iter_subtrees() if d.data in _DEFINITIONS
        ]
        owners: dict[str, set] = {}  # name -> the scopes that assign it or take it as a parameter
        for index, (definition, statements) in enumerate(scopes):
            params = definition.children[1] if definition is not None else None
            for param in params.children if params is not None else []:
                owners.setdefault(str(param.children[0]), set()).update((index, -1))
            for node in _own_nodes(statements):
                if node.data == "global_stmt":  # the program's, or the installation's (set outside the program)
                    owners.setdefault(str(node.children[0]), set()).add(-2)
                elif node.data == "local_stmt" or (node.data == "assign" and _assigned(node)):
                    owners.setdefault(_assigned(node) or str(node.children[0]), set()).add(index)
        for index, (_definition, statements) in enumerate(scopes):
            nodes = list(_own_nodes(statements))
            assigns: dict[str, list] = {}
            targets = set()
            for node in nodes:
                if node.data == "assign" and _assigned(node):
                    assigns.setdefault(_assigned(node), []).append(node)
                    targets.add(id(node.children[0]))
                elif node.data in ("global_stmt", "local_stmt"):
                    assigns.setdefault(str(node.children[0]), []).append(node)
            loops = [(_line(n)[0], _last_line(n)) for n in nodes if n.data == "while_stmt"]
            called = {id(call.children[0]) for _name, call in _calls(Tree("scope", list(statements)))}
            reported = set()
            for node in nodes:
                if node.data != "var" or id(node) in targets or id(node) in called:
                    continue
                name = str(node.children[0])
                if name in reported or name not in assigns or owners.get(name) != {index}:
                    continue
                at = _line(node)
                earlier = [a for a in assigns[name] if _line(a) < at and not _holds(a, at)]
                together = any(low <= at[0] <= high and any(low <= _line(a)[0] <= high for a in assigns[name])
                               for low, high in loops)  # fmt: skip
                if not earlier and not together:
                    reported.add(name)
                    self.add(node, "warning", "read-before-assign", f"{name} is read before it is assigned (the "
                             f"assignment on line {_line(assigns[name][0])[0]}): run stops here")  # fmt: skip

    # --- waits ----------------------------------------------------------------------------------
    def waits(self) -> None:
        for loop in self.tree.find_data("while_stmt"):
            condition, body = loop.children
            reads = [name for name, _call in _calls(condition) if any(part in name for part in INPUT_READS)]
            if len(reads) != 1:  # none, or a second input the loop also ends on (an operator's stop)
                continue
            statements = [c for c in body.children if isinstance(c, Tree) and c.data != "label_stmt"]
            only_waits = all(
                s.data == "expr_stmt"
                and isinstance(s.children[0], Tree)
                and s.children[0].data == "call"
                and str(s.children[0].children[0].children[0]) in WAIT_BODY
                for s in statements
            )
            if only_waits:
                self.add(
                    loop,
                    "warning",
                    "wait-without-timeout",
                    f"a wait on {reads[0]}(...) without a timeout: the program waits for ever if it never "
                    "comes (count the cycles and stop after a time)",
                )

    # --- motion before the TCP is set -----------------------------------------------------------
    def motion_before_tcp(self) -> None:
        state = {"tcp": False, "reported": False}
        main = self.main_statements()
        self.walk(main, state, set())

    def main_statements(self) -> list:
        top = [c for c in self.tree.children if isinstance(c, Tree)]
        defs = [c for c in top if c.data == "funcdef"]
        if len(top) == 1 and len(defs) == 1:
            return [c for c in defs[0].children[2].children if isinstance(c, Tree)]
        return [c for c in top if c.data not in ("funcdef", "threaddef")]

    def walk(self, statements, state: dict, entered: set) -> None:
        for statement in statements:
            if state["reported"] or statement.data in ("funcdef", "threaddef"):
                continue
            if statement.data in ("if_stmt", "while_stmt", "elif_clause", "else_clause", "body"):
                for child in statement.children:
                    if isinstance(child, Tree) and child.data in ("body", "elif_clause", "else_clause"):
                        self.walk(child.children if child.data == "body" else [child], state, entered)
                    elif isinstance(child, Tree):
                        self.walk_calls(child, state, entered)
                continue
            self.walk_calls(statement, state, entered)

    def walk_calls(self, node, state: dict, entered: set) -> None:
        for name, call in sorted(_calls(node), key=lambda c: _line(c[1])):
            if state["reported"]:
                return
            if name == "set_tcp":
                state["tcp"] = True
            elif name in MOTION and not state["tcp"]:
                state["reported"] = True
                self.add(
                    call,
                    "warning",
                    "motion-before-tcp",
                    f"{name} before the program sets its TCP (set_tcp): the arm moves with whatever TCP the "
                    "installation holds",
                )
            elif name in self.functions and name not in entered:
                entered.add(name)
                body = self.functions[name].children[2]
                self.walk([c for c in body.children if isinstance(c, Tree)], state, entered)

    # --- speeds ---------------------------------------------------------------------------------
    def speeds(self) -> None:
        fastest = max(self.joint_max_deg_s)
        for name, call in _calls(self.tree):
            if name not in ("movej", "servoj", "speedj"):
                continue
            args = call.children[1].children if call.children[1] is not None else []
            positional = [a for a in args if not (isinstance(a, Tree) and a.data == "kwarg")]
            named = {str(a.children[0]): a.children[1] for a in args if isinstance(a, Tree) and a.data == "kwarg"}
            if name in ("movej", "servoj"):
                node = named.get("v", positional[2] if len(positional) > 2 else None)
                value = None if node is None else _number(node)
                if value is not None and math.degrees(abs(value)) > fastest + 1e-6:
                    self.add(
                        node,
                        "warning",
                        "speed-over-arm",
                        f"{name} v={value:g} rad/s ({math.degrees(value):.0f} deg/s) is over the fastest joint of "
                        f"{self.arm_name} ({fastest:.0f} deg/s)",
                    )
                continue
            node = named.get("qd", positional[0] if positional else None)
            if isinstance(node, Tree) and node.data == "list_lit":
                for axis, element in enumerate(c for c in node.children if c is not None):
                    value = _number(element)
                    top = self.joint_max_deg_s[axis] if axis < 6 else fastest
                    if value is not None and math.degrees(abs(value)) > top + 1e-6:
                        self.add(
                            element,
                            "warning",
                            "speed-over-arm",
                            f"speedj: axis {axis + 1} at {value:g} rad/s ({math.degrees(value):.0f} deg/s) is over "
                            f"its {top:.0f} deg/s on {self.arm_name}",
                        )


def check_files(dialect, files: list, options=None) -> list[Finding]:
    """Every finding of URScript files (each file is a program of its own)."""
    interpreter = dialect.module("interpreter")
    findings: list[Finding] = []
    for source in files:
        try:
            tree = interpreter.parse(source.text, source.name)
        except RunError as exc:
            findings.append(finding_of(exc, [source], "syntax"))
            continue
        except RecursionError:
            findings.append(finding_of(f"{source.name}: statements or expressions nested too deeply", [source]))
            continue
        builtins = interpreter.URScriptCompiler(source.name).builtins
        found = Checker(tree, source.name, builtins, getattr(options, "arm", None)).run()
        findings.extend(sorted(found, key=lambda f: (f.line, f.column)))
        if any(f.severity in ("error", "unsupported") for f in found):
            continue  # loading would stop at the first of them again
        try:
            interpreter.load(source.text, source.name)
        except RunError as exc:
            findings.append(finding_of(exc, [source]))
        except RecursionError:
            findings.append(finding_of(f"{source.name}: statements or expressions nested too deeply", [source]))
    return findings
