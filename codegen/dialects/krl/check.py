"""`codegen check` of KRL programs: every error the controller's compiler or the interpreter finds, and field checks."""

from __future__ import annotations

import re

from lark import Token, Tree

from codegen.dialects.core.files import Finding, SourceFile
from codegen.dialects.core.values import RunError
from codegen.dialects.krl.builtins import SIMPLE  # the simple data types: a value, not a structure of named parts
from codegen.dialects.krl.modules import Linker, routine_name
from codegen.dialects.krl.syntax import parse

NAME_MAX = 24  # characters of a KRL name (KSS 8 programming manual, names: up to 24 characters)
SYNTAX_MAX = 20  # syntax errors reported per file (each further one is found with the bad line left out)
WHERE = re.compile(r"^(?P<file>.+?):(?P<line>\d+):(?P<column>\d+): (?P<message>.*)$", re.DOTALL)
CODES = (  # (words of a message, code, severity)
    ("syntax error", "syntax", "error"),
    ("not modelled", "unsupported", "unsupported"),
    ("not supported", "unsupported", "unsupported"),
    ("undefined variable", "undefined-name", "error"),
    ("unknown routine", "undefined-routine", "error"),
    ("no routine", "undefined-routine", "error"),
    ("type error", "type", "error"),
    ("cannot assign", "type", "error"),
    ("unknown type", "type", "error"),
    ("is not a value of", "type", "error"),
)
# Statements after which the arm has arrived: they stop the advance run (KSS 8 programming manual for system
# integrators, "Advance run stop"), unless a CONTINUE stands before the I/O access.
STOPS = ("wait_sec", "wait_for", "halt_stmt")


def finding_of(exc: RunError, default_file: str) -> Finding:
    text = str(exc)
    match = WHERE.match(text)
    if match:
        file, line, column, message = match["file"], int(match["line"]), int(match["column"]), match["message"]
    else:
        file, line, column, message = default_file, 0, 0, text
    if not match and ": " in text and text.split(": ", 1)[0].endswith((".src", ".dat")):
        file, message = text.split(": ", 1)
    code, severity = next(((c, s) for words, c, s in CODES if words in message), ("load", "error"))
    return Finding(file, line, column, severity, code, message)


def repaired(file: SourceFile, findings: list[Finding]) -> SourceFile:
    """The file with each line that does not parse left out (its syntax error a finding), so that the rest is
    checked too."""
    lines = file.text.split("\n")
    for _ in range(SYNTAX_MAX):
        try:
            parse("\n".join(lines), file.name, positions=False)
            return SourceFile(file.name, "\n".join(lines))
        except RunError as exc:
            finding = finding_of(exc, file.name)
            findings.append(finding)
            if not 1 <= finding.line <= len(lines) or not lines[finding.line - 1].strip():
                break
            lines[finding.line - 1] = ""
    return SourceFile(file.name, "")


def check_files(files: list[SourceFile]) -> list[Finding]:
    """Every finding of one program's files (as KRL.programs groups them): syntax, what the interpreter does not
    model, undefined names and routines, type errors, and the field checks below."""
    findings: list[Finding] = []
    texts = [repaired(f, findings) for f in files]
    errors: list[RunError] = []
    trees = []
    try:
        Linker(texts, errors).link()
    except RunError as exc:
        errors.append(exc)
    findings.extend(finding_of(e, files[0].name) for e in errors)
    for f in texts:
        try:
            trees.append((f.name, parse(f.text, f.name)))
        except RunError:
            continue
    inputs = {"$IN"} | {name for _file, tree in trees for name in _input_signals(tree)}
    for name, tree in trees:
        findings.extend(long_names(name, tree))
        findings.extend(waits(name, tree, inputs))
        findings.extend(early_outputs(name, tree))
        findings.extend(unset_locals(name, tree))
        findings.extend(zero_divisors(name, tree))
        findings.extend(aggregates_to_scalars(name, tree, trees))
        findings.extend(negative_waits(name, tree))
    if trees:
        findings.extend(unset_data(trees))
        findings.extend(constant_indexes(trees))
    if trees:
        findings.extend(unset_frames(trees))
    unique = {}
    for f in findings:
        unique.setdefault((f.file, f.line, f.code, f.message), f)
    return sorted(unique.values(), key=lambda f: (f.file, f.line, f.column))


# --- field checks ----------------------------------------------------------------------------------


def _declared_names(tree):
    for sub in tree.iter_subtrees_topdown():
        if sub.data == "decl_item" or sub.data == "label" or sub.data == "param":
            yield sub.children[0]
        elif sub.data in ("def_routine", "def_function"):
            yield sub.children[1 if sub.data == "def_routine" else 2]
        elif sub.data in ("signal_decl",):
            yield sub.children[0]
        elif sub.data in ("enum_decl", "struc_decl"):
            yield sub.children[1]


def long_names(name: str, tree) -> list[Finding]:
    out = []
    for token in _declared_names(tree):
        if isinstance(token, Token) and len(str(token)) > NAME_MAX:
            out.append(
                Finding(
                    name,
                    token.line,
                    token.column,
                    "error",
                    "name-too-long",
                    f"{token} has {len(str(token))} characters: a KRL name has up to {NAME_MAX}",
                )
            )
    return out


def _mentions(node, names: set[str]) -> bool:
    return any(sub.data == "var" and str(sub.children[0]).upper() in names for sub in node.iter_subtrees())


def _input_signals(tree) -> set[str]:
    """The names SIGNAL gives inputs in a file."""
    out = set()
    for sub in tree.iter_subtrees():
        if sub.data == "signal_decl":
            bank = sub.children[1].children[0] if isinstance(sub.children[1], Tree) else None
            if isinstance(bank, Tree) and bank.data == "var" and str(bank.children[0]).upper() == "$IN":
                out.add(str(sub.children[0]).upper())
    return out


def waits(name: str, tree, inputs: set[str]) -> list[Finding]:
    """WAIT FOR on an input without a timeout: KRL's WAIT FOR has none; a program that does not also wait for
    a timer ($TIMER_FLAG[n], $TIMER[n]) waits for ever if the device never answers."""
    out = []
    for sub in tree.iter_subtrees_topdown():
        if sub.data == "wait_for" and isinstance(sub.children[0], Tree):
            cond = sub.children[0]
            if _mentions(cond, inputs) and not _mentions(cond, {"$TIMER_FLAG", "$TIMER", "$ROB_TIMER"}):
                line, column = _start(sub)
                out.append(
                    Finding(
                        name,
                        line,
                        column,
                        "warning",
                        "wait-without-timeout",
                        "WAIT FOR an input without a timeout: the program waits for ever if the device "
                        "never answers (wait for a $TIMER_FLAG too, or poll with a time limit)",
                    )
                )
    return out


def _start(node) -> tuple[int, int]:
    meta = getattr(node, "meta", None)
    if meta is not None and not getattr(meta, "empty", True):
        return meta.line, meta.column
    for token in node.scan_values(lambda t: isinstance(t, Token)):
        return token.line, token.column
    return 0, 0


def _is_output_store(node) -> bool:
    if node.data != "assign":
        return node.data == "call_stmt" and str(node.children[0]).upper() == "PULSE"
    target = node.children[0]
    return (
        isinstance(target, Tree)
        and target.data == "index"
        and isinstance(target.children[0], Tree)
        and target.children[0].data == "var"
        and str(target.children[0].children[0]).upper() == "$OUT"
    )


def early_outputs(name: str, tree) -> list[Finding]:
    """An output set after CONTINUE, after a motion with no advance-run stop between: the controller sets it
    while the arm still moves to the point before (the advance run), not when the arm is there; and an output
    set without CONTINUE right after an approximated motion: its advance-run stop ends the approximation."""
    out = []
    for body in tree.iter_subtrees_topdown():
        if body.data != "body":
            continue
        moved, approximated, continued = None, None, False
        for stmt in (c for c in body.children if isinstance(c, Tree)):
            if stmt.data in ("motion_stmt", "circ_stmt"):
                moved = stmt
                approximated = any(isinstance(c, Tree) and c.data == "approx" for c in stmt.children)
            elif stmt.data == "continue_stmt":
                continued = True
                continue
            elif _is_output_store(stmt) and moved is not None:
                line, column = _start(stmt)
                if continued:
                    out.append(
                        Finding(
                            name,
                            line,
                            column,
                            "warning",
                            "output-in-advance-run",
                            f"the output is set in the advance run (CONTINUE): while the arm still moves to "
                            f"the point of line {_start(moved)[0]}, not when it is there",
                        )
                    )
                elif approximated:
                    out.append(
                        Finding(
                            name,
                            line,
                            column,
                            "warning",
                            "approximation-lost",
                            f"setting an output stops the advance run: the approximation of line "
                            f"{_start(moved)[0]} is not possible (TRIGGER or CONTINUE)",
                        )
                    )
                moved = None
            elif stmt.data in STOPS:
                moved = None
            continued = False
    return out


def _root_var(node):
    """The variable an assignment target or argument stands on (N, N.X, N[2], N[]), None if none."""
    while isinstance(node, Tree) and node.data != "var":
        if not node.children:
            return None
        node = node.children[0]
    return str(node.children[0]).upper() if isinstance(node, Tree) else None


def _set_names(node) -> set:
    """The variables a tree may set: assignment targets, FOR counters, arguments (an OUT parameter's)."""
    out = set()
    for sub in node.iter_subtrees():
        if sub.data == "assign":
            out.add(_root_var(sub.children[0]))
        elif sub.data == "for_stmt":
            out.add(str(sub.children[0]).upper())
        elif sub.data == "args":
            out.update(_root_var(a) for a in sub.children if isinstance(a, Tree))
    return out


def _unset_read(file: str, token, where: str) -> Finding:
    return Finding(
        file,
        token.line,
        token.column,
        "warning",
        "unset-variable",
        f"{token} is read but nothing in {where} sets it: KSS stops here (variable value invalid)",
    )


def unset_data(trees) -> list[Finding]:
    """A data list's variable declared without a value that no module of the program sets, read by a routine
    (one without a variable of its own of that name)."""
    unset = {}
    for _file, tree in trees:
        for defdat in (n for n in tree.children if isinstance(n, Tree) and n.data == "defdat"):
            for item in defdat.iter_subtrees_topdown():
                if item.data == "decl_item" and item.children[1] is None and item.children[2] is None:
                    unset.setdefault(str(item.children[0]).upper(), item.children[0])
    for _file, tree in trees:
        for key in _set_names(tree):
            unset.pop(key, None)
    out = []
    for file, tree in trees:
        for routine in (n for n in tree.children if isinstance(n, Tree) and n.data in ("def_routine", "def_function")):
            own = {str(i.children[0]).upper() for i in routine.iter_subtrees() if i.data in ("decl_item", "param")}
            for sub in routine.iter_subtrees_topdown():
                key = str(sub.children[0]).upper() if sub.data == "var" else None
                if key in unset and key not in own:
                    out.append(_unset_read(file, sub.children[0], "the program's files"))
                    del unset[key]  # one finding a variable
    return out




def _declared_types(node) -> dict[str, tuple[str, int]]:
    """The variables declared right in a routine or data list (name -> its type, upper case, and its number of
    array dimensions, 0: not an array)."""
    out = {}
    for decl in node.iter_subtrees():
        if decl.data != "decl":
            continue
        tokens = [c for c in decl.children if isinstance(c, Token)]
        type_name = str(tokens[-1]).upper()
        for item in (c for c in decl.children if isinstance(c, Tree) and c.data == "decl_item"):
            dims = item.children[1]
            count = len(dims.children) if isinstance(dims, Tree) and dims.data == "dims" else 0
            out.setdefault(str(item.children[0]).upper(), (type_name, count))
    return out


def aggregates_to_scalars(name: str, tree, trees) -> list[Finding]:
    """An aggregate ({X 1.0}) assigned to an INT, REAL, BOOL or CHAR variable or array element: KSS refuses it,
    run stops there ("cannot assign an aggregate"); the type is known from the declaration."""
    shared = {}  # the data lists' variables: every routine of the program sees them
    for _file, other in trees:
        for defdat in (n for n in other.children if isinstance(n, Tree) and n.data == "defdat"):
            shared.update(_declared_types(defdat))
    out = []
    for routine in (n for n in tree.children if isinstance(n, Tree) and n.data in ("def_routine", "def_function")):
        params = {str(p.children[0]).upper() for p in routine.iter_subtrees() if p.data == "param"}
        types = {**shared, **_declared_types(routine)}
        for assign in routine.iter_subtrees_topdown():
            value = assign.children[1] if assign.data == "assign" else None
            if not (isinstance(value, Tree) and value.data == "aggregate"):
                continue
            target, indexes = assign.children[0], 0
            if isinstance(target, Tree) and target.data == "index":
                target, indexes = target.children[0], len(target.children) - 1
            if not (isinstance(target, Tree) and target.data == "var"):
                continue
            key = str(target.children[0]).upper()
            type_name, dims = types.get(key, ("", -1))
            if key not in params and type_name in SIMPLE and dims == indexes:
                line, column = _start(assign)
                message = f"an aggregate assigned to {target.children[0]}, declared {type_name}: only a structure "
                out.append(Finding(name, line, column, "error", "type", message + "takes one (KSS: cannot assign it)"))
    return out


def negative_waits(name: str, tree) -> list[Finding]:
    """WAIT SEC with a negative literal time: the controller does not wait (run warns where the line runs)."""
    out = []
    for sub in tree.iter_subtrees_topdown():
        time = sub.children[0] if sub.data == "wait_sec" else None
        if isinstance(time, Tree) and time.data == "neg" and isinstance(time.children[0], Tree):
            inner = time.children[0]
            if inner.data == "number" and float(str(inner.children[0])) > 0:
                line, column = _start(sub)
                message = f"WAIT SEC -{inner.children[0]}: a negative time does not wait (taken as 0 s)"
                out.append(Finding(name, line, column, "warning", "negative-wait", message))
    return out


def zero_divisors(name: str, tree) -> list[Finding]:
    """A division by the literal 0: run stops there ("division by zero") when the line runs."""
    out = []
    for sub in tree.iter_subtrees_topdown():
        divisor = sub.children[-1] if sub.data == "div" else None
        if isinstance(divisor, Tree) and divisor.data == "number" and float(str(divisor.children[0])) == 0:
            line, column = _start(sub)
            out.append(Finding(name, line, column, "error", "division-by-zero", "division by zero"))
    return out


def _dims(item) -> tuple[int, ...] | None:
    """A decl_item's array sizes (DECL INT A[10, 3]: (10, 3)), None: not an array."""
    dims = item.children[1]
    if not isinstance(dims, Tree) or dims.data != "dims":
        return None
    return tuple(int(str(d)) for d in dims.children)


def _literal_indexes(node) -> tuple[int, ...] | None:
    """An index node's subscripts where every one is a whole-number literal, else None."""
    subs = node.children[1:]
    if not subs or not all(isinstance(s, Tree) and s.data == "number" and str(s.children[0]).isdigit() for s in subs):
        return None
    return tuple(int(str(s.children[0])) for s in subs)


def constant_indexes(trees) -> list[Finding]:
    """An array read or written at literal subscripts beyond its declared size (KRL arrays run from 1): run stops
    there with "index out of range" when the line runs; the size is known from the declaration."""
    shared = {}  # the data lists' arrays: every routine of the program sees them
    for _file, tree in trees:
        for defdat in (n for n in tree.children if isinstance(n, Tree) and n.data == "defdat"):
            for item in (i for i in defdat.iter_subtrees_topdown() if i.data == "decl_item"):
                if _dims(item) is not None:
                    shared[str(item.children[0]).upper()] = _dims(item)
    out = []
    for file, tree in trees:
        for routine in (n for n in tree.children if isinstance(n, Tree) and n.data in ("def_routine", "def_function")):
            own = {
                str(i.children[0]).upper(): _dims(i) if i.data == "decl_item" else None
                for i in routine.iter_subtrees()
                if i.data in ("decl_item", "param")
            }
            for sub in routine.iter_subtrees_topdown():
                if sub.data != "index" or not (isinstance(sub.children[0], Tree) and sub.children[0].data == "var"):
                    continue
                name = str(sub.children[0].children[0]).upper()
                dims, at = own[name] if name in own else shared.get(name), _literal_indexes(sub)
                if dims is None or at is None or len(at) != len(dims):
                    continue
                for value, size in zip(at, dims, strict=True):
                    if not 1 <= value <= size:
                        line, column = _start(sub)
                        out.append(
                            Finding(
                                file,
                                line,
                                column,
                                "error",
                                "index",
                                f"index {value} out of range: {sub.children[0].children[0]} is declared with "
                                f"{size} elements (1..{size})",
                            )
                        )
                        break
    return out


def unset_locals(name: str, tree) -> list[Finding]:
    """A routine's own variable (DECL in a .src has no value) read but set nowhere in the routine: not by an
    assignment, a FOR, or as an argument (a routine or built-in may set it through an OUT parameter). KSS stops
    where it is read ("variable value invalid"); run finds it only when the read runs."""
    out = []
    for routine in (n for n in tree.children if isinstance(n, Tree) and n.data in ("def_routine", "def_function")):
        body = routine.children[-1]
        params = {str(p.children[0]).upper() for p in routine.iter_subtrees() if p.data == "param"}
        local = {}
        for decl in (c for c in body.children if isinstance(c, Tree) and c.data == "decl"):
            for item in (c for c in decl.children if isinstance(c, Tree) and c.data == "decl_item"):
                key = str(item.children[0]).upper()
                if item.children[1] is None and item.children[2] is None and key not in params:
                    local[key] = item.children[0]
        if not local:
            continue
        set_names = _set_names(body)
        reported = set()
        for sub in body.iter_subtrees_topdown():
            if sub.data != "var":
                continue
            key = str(sub.children[0]).upper()
            if key in local and key not in set_names and key not in reported:
                reported.add(key)
                out.append(_unset_read(name, sub.children[0], routine_name(routine)))
        out.extend(_reads_before_set(name, routine, {k: v for k, v in local.items() if k in set_names}))
    return out


_LOOPS = ("while_stmt", "for_stmt", "loop_stmt", "repeat_stmt")


def _setters(body, names: set[str]) -> tuple[dict[str, list], set[int]]:
    """The statements that may set each of the names (an assignment to it or a part of it, a FOR on it, a call
    passing it), and the var nodes that are such a setting itself (an assignment's target, an argument)."""
    setters: dict[str, list] = {}
    setting: set[int] = set()
    for sub in body.iter_subtrees():
        if sub.data == "assign":
            targets = [sub.children[0]]
        elif sub.data == "for_stmt":
            key = str(sub.children[0]).upper()
            if key in names:
                setters.setdefault(key, []).append(sub)
            continue
        elif sub.data in ("call_stmt", "call") and isinstance(sub.children[1], Tree):
            targets = [a for a in sub.children[1].children if isinstance(a, Tree)]
        else:
            continue
        for target in targets:
            root = target
            while isinstance(root, Tree) and root.data != "var" and root.children:
                root = root.children[0]
            key = str(root.children[0]).upper() if isinstance(root, Tree) and root.data == "var" else None
            if key in names:
                setters.setdefault(key, []).append(sub)
                setting.add(id(root))
    return setters, setting


def _reads_before_set(file: str, routine, local: dict) -> list[Finding]:
    """A routine's own variable read before the first statement that may set it (in a routine without GOTO, the
    read and every setting not in one loop: the read cannot come after a setting): KSS stops at the read
    ("variable value invalid"); run finds it only when the read runs."""
    body = routine.children[-1]
    if not local or any(True for _ in body.find_data("goto_stmt")):
        return []
    setters, setting = _setters(body, set(local))
    loops = [(_start(n)[0], _last_line(n)) for n in body.iter_subtrees() if n.data in _LOOPS]
    out, reported = [], set()
    for statement in body.iter_subtrees_topdown():
        if statement.data != "var" or id(statement) in setting:
            continue
        key, token = str(statement.children[0]).upper(), statement.children[0]
        if key not in setters or key in reported:
            continue
        at = (token.line, token.column)
        earlier = [s for s in setters[key] if _start(s) < at and not _inside(token, s)]
        together = any(
            low <= token.line <= high and any(low <= _start(s)[0] <= high for s in setters[key]) for low, high in loops
        )
        if not earlier and not together:
            reported.add(key)
            message = f"{token} is read before anything in {routine_name(routine)} sets it: KSS stops here "
            message += "(variable value invalid)"
            out.append(Finding(file, token.line, token.column, "warning", "unset-variable", message))
    return out


def _last_line(node) -> int:
    """The line of a statement's last token (its end, as far as the tree keeps it)."""
    return max((t.line for t in node.scan_values(lambda v: isinstance(v, Token)) if t.line), default=0)


def _inside(token, node) -> bool:
    """Whether a token is part of a statement."""
    return _start(node) <= (token.line, token.column) and token.line <= _last_line(node)


FRAME_SETTERS = {"#INITMOV", "#TOOL", "#BASE", "#FRAMES", "#PTP_PARAMS", "#CP_PARAMS"}


def unset_frames(trees) -> list[Finding]:
    """The program's first motion before $TOOL and $BASE are set (by an assignment, BAS(#INITMOV), BAS(#TOOL /
    #BASE / #PTP_PARAMS / #CP_PARAMS / #FRAMES) or the motion's WITH): it moves with the tool and base the
    previous program left. Followed through the main routine and the routines it calls, in program order."""
    name, tree = trees[0]
    routines = {
        routine_name(n): (file, n)
        for file, t in trees
        for n in t.children
        if isinstance(n, Tree) and n.data in ("def_routine", "def_function")
    }
    main = next((n for n in tree.children if isinstance(n, Tree) and n.data == "def_routine"), None)
    if main is None:
        return []
    state = {"tool": False, "base": False, "seen": set(), "moved": False}
    return _walk(main, name, routines, state)


def _walk(node, file: str, routines: dict, state: dict) -> list[Finding]:
    for sub in node.iter_subtrees_topdown():
        if sub.data == "assign" or sub.data == "with_item":
            root = sub.children[0]
            while isinstance(root, Tree) and root.data != "var":
                root = root.children[0]
            target = str(root.children[0]).upper() if isinstance(root, Tree) else ""
            state["tool"] |= target == "$TOOL"
            state["base"] |= target == "$BASE"
        elif sub.data in ("call_stmt", "call"):
            called = str(sub.children[0]).upper()
            args = sub.children[1].children if sub.children[1] is not None else []
            if called == "BAS" and args and isinstance(args[0], Tree) and args[0].data == "enum":
                command = "#" + str(args[0].children[0]).upper()
                if command in FRAME_SETTERS:
                    state["tool"] |= command != "#BASE"
                    state["base"] |= command != "#TOOL"
            elif called in routines and called not in state["seen"]:
                state["seen"].add(called)
                found = _walk(routines[called][1], routines[called][0], routines, state)
                if state["moved"]:
                    return found
        elif sub.data in ("motion_stmt", "circ_stmt"):
            with_clause = next((c for c in sub.children if isinstance(c, Tree) and c.data == "with_clause"), None)
            if with_clause is not None:
                _walk(with_clause, file, routines, state)
            state["moved"] = True
            if not (state["tool"] and state["base"]):
                missing = " and ".join(n for n, ok in (("$TOOL", state["tool"]), ("$BASE", state["base"])) if not ok)
                line, column = _start(sub)
                return [
                    Finding(
                        file,
                        line,
                        column,
                        "warning",
                        "motion-before-tool-base",
                        f"a motion before {missing} is set (BAS(#INITMOV, 0), the inline form's "
                        "BAS(#PTP_PARAMS ...), or an assignment): it moves with what the previous program "
                        "left",
                    )
                ]
            return []
    return []
