"""`codegen check` of KRL programs: every error the controller's compiler or the interpreter finds, and field checks."""

from __future__ import annotations

import re

from lark import Token, Tree

from codegen.dialects.core.files import Finding, SourceFile
from codegen.dialects.core.kept import STORE
from codegen.dialects.core.literals import literal_number
from codegen.dialects.core.parsing import node_start
from codegen.dialects.core.values import RunError
from codegen.dialects.krl import KRL, eki
from codegen.dialects.krl.builtins import SIMPLE  # the simple data types: a value, not a structure of named parts
from codegen.dialects.krl.compiler import KRLCompiler
from codegen.dialects.krl.modules import Linker
from codegen.dialects.krl.syntax import parse
from codegen.dialects.krl.unset import unset_data, unset_frames, unset_locals

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
    if not match and ": " in text and text.split(": ", 1)[0].endswith((*KRL.suffixes, ".dat")):
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


def check_files(files: list[SourceFile], channels: frozenset | None = None) -> list[Finding]:
    """Every finding of one program's files (as KRL.programs groups them): syntax, what the interpreter does not
    model, undefined names and routines, type errors, and the field checks below; given `channels` (the names of
    the Ethernet KRL configurations among the program's files), each EKI_Init of a channel without one."""
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
    inputs = frozenset({"$IN"} | {name for file, tree in trees for name in STORE.by_unit(_input_signals, file, tree)})
    shared = _shared_types(trees)
    shared_key = tuple(sorted(shared.items()))
    for name, tree in trees:
        for walk in (long_names, early_outputs, unset_locals, zero_divisors, negative_waits):
            findings.extend(STORE.by_unit(walk, name, tree))
        findings.extend(STORE.by_unit(waits, name, tree, inputs, key=inputs))
        findings.extend(STORE.by_unit(aggregates_to_scalars, name, tree, shared, key=shared_key))
        if channels is not None:
            findings.extend(eki.unconfigured(name, tree, channels))
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


def _input_signals(_name: str, tree) -> set[str]:
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
                line, column = node_start(sub)
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
                line, column = node_start(stmt)
                if continued:
                    out.append(
                        Finding(
                            name,
                            line,
                            column,
                            "warning",
                            "output-in-advance-run",
                            f"the output is set in the advance run (CONTINUE): while the arm still moves to "
                            f"the point of line {node_start(moved)[0]}, not when it is there",
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
                            f"{node_start(moved)[0]} is not possible (TRIGGER or CONTINUE)",
                        )
                    )
                moved = None
            elif stmt.data in STOPS:
                moved = None
            continued = False
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


def _shared_types(trees) -> dict[str, tuple[str, int]]:
    """The data lists' variables (every routine of the program sees them) and their types, as _declared_types."""
    shared = {}
    for _file, other in trees:
        for defdat in (n for n in other.children if isinstance(n, Tree) and n.data == "defdat"):
            shared.update(_declared_types(defdat))
    return shared


def aggregates_to_scalars(name: str, tree, shared: dict) -> list[Finding]:
    """An aggregate ({X 1.0}) assigned to an INT, REAL, BOOL or CHAR variable or array element: KSS refuses it,
    run stops there ("cannot assign an aggregate"); the type is known from the declaration (`shared`: the data
    lists', _shared_types)."""
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
                line, column = node_start(assign)
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
            if inner.data == "number" and (literal_number(inner, KRLCompiler.number) or 0) > 0:
                line, column = node_start(sub)
                message = f"WAIT SEC -{inner.children[0]}: a negative time does not wait (taken as 0 s)"
                out.append(Finding(name, line, column, "warning", "negative-wait", message))
    return out


def zero_divisors(name: str, tree) -> list[Finding]:
    """A division by the literal 0: run stops there ("division by zero") when the line runs."""
    out = []
    for sub in tree.iter_subtrees_topdown():
        divisor = sub.children[-1] if sub.data == "div" else None
        if literal_number(divisor, KRLCompiler.number) == 0:
            line, column = node_start(sub)
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
    key = tuple(sorted(shared.items()))
    return [f for file, tree in trees for f in STORE.by_unit(_indexes_out_of_range, file, tree, shared, key=key)]


def _indexes_out_of_range(file: str, tree, shared: dict) -> list[Finding]:
    out = []
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
                    line, column = node_start(sub)
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
