"""`codegen check` for RAPID: each syntax error, refusal, undefined name, type error and field check of a task."""

from __future__ import annotations

import re
from dataclasses import replace

from lark import Tree

from codegen.dialects.core.files import Finding, SourceFile
from codegen.dialects.core.literals import literal_number as _number
from codegen.dialects.core.values import RunError
from codegen.dialects.rapid import typecheck
from codegen.dialects.rapid.compiler import parse
from codegen.dialects.rapid.predefined import PREDEFINED
from codegen.dialects.rapid.task import load_task
from codegen.dialects.rapid.types import STRING_MAX

SYNTAX_MAX = 10  # syntax errors reported per file (each further one after blanking the line of the one before)
_SYNTAX = re.compile(r"^(?P<file>.*?):(?P<line>\d+):(?P<column>\d+): (?P<message>.*)$", re.DOTALL)
# A syntax error at one of these words is most likely the echo of an earlier one (its statement was blanked).
_ECHO = re.compile(r"at '(ENDIF|ENDWHILE|ENDFOR|ENDTEST|ENDPROC|ENDFUNC|ENDTRAP|ENDMODULE|ENDRECORD|ELSE|ELSEIF|"
                   r"CASE|DEFAULT|ERROR|UNDO|BACKWARD)'", re.IGNORECASE)  # fmt: skip
_OPENS = re.compile(r"\s*(LOCAL\s+)?(MODULE|PROC|FUNC|TRAP|RECORD|IF|WHILE|FOR|TEST|ELSE|ELSEIF|ERROR)\b", re.I)
INPUT_FUNCTIONS = {"DINPUT", "TESTDI", "GINPUT", "AINPUT"}


def syntax_findings(files: list[SourceFile]) -> list[Finding]:
    """Each file's syntax errors: the first, then (the line blanked) the next, up to SYNTAX_MAX, stopping at an
    error that is likely the first one's echo (an END... or ELSE of a blanked statement)."""
    found = []
    for f in files:
        lines = f.text.split("\n")
        for count in range(SYNTAX_MAX):
            try:
                parse("\n".join(lines), f.name, positions=False)
                break
            except RunError as exc:
                match = _SYNTAX.match(str(exc))
                if match is None:
                    found.append(Finding(f.name, 0, 0, "error", "syntax", str(exc)))
                    break
                if count and _ECHO.search(match["message"]):
                    break
                line = int(match["line"])
                found.append(Finding(f.name, line, int(match["column"]), "error", "syntax", match["message"]))
                if not 1 <= line <= len(lines) or _OPENS.match(lines[line - 1]):
                    break  # blanking a line that opens a block would make every line after it an error
                lines[line - 1] = ""
    return found


def check_task(files: list[SourceFile], max_tcp_mm_s: float | None = None, entry: str | None = None) -> list[Finding]:
    """Every finding of the task's files (codegen.dialects.core.files.Finding), in file and line order; entry: the
    routine the task starts at (a module loaded into another task's, which has the main: no main needed here)."""
    findings = syntax_findings(files)
    if findings:
        return findings
    out: dict = {}
    try:
        load_task(files, findings, out, entry=entry)
    except RunError as exc:  # a refusal the compiler does not report as a finding
        match = _SYNTAX.match(str(exc))
        if match:
            findings.append(Finding(match["file"], int(match["line"]), int(match["column"]), "error", "load",
                                    match["message"]))  # fmt: skip
        else:
            findings.append(Finding(files[0].name, 0, 0, "error", "load", str(exc)))
    trees = out.get("trees") or [(f.name, parse(f.text, f.name)) for f in files]
    compiler = out.get("compiler")
    if compiler is not None:
        findings += typecheck.check(compiler, trees)
    inputs = {k for k, v in compiler.signal_kinds.items() if v in ("DI", "GI", "AI")} if compiler else set()
    findings += field_checks(trees, max_tcp_mm_s, inputs)
    findings += constant_indexes(trees)
    findings += zero_divisors(trees)
    if compiler is not None:
        findings += long_strings(trees, compiler.string_value)
    order = {f.name: i for i, f in enumerate(files)}
    return sorted(set(findings), key=lambda f: (order.get(f.file, len(order)), f.line, f.column, f.code))


def _warning(file: str, node, code: str, message: str) -> Finding:
    meta = getattr(node, "meta", None)
    line = getattr(node, "line", None) or (meta.line if meta is not None and not meta.empty else 0)
    column = getattr(node, "column", None) or (meta.column if meta is not None and not meta.empty else 0)
    return Finding(file, line or 0, column or 0, "warning", code, message)


def _calls(tree):
    for node in tree.iter_subtrees_topdown():
        if node.data in ("proc_call", "call"):
            yield node, str(node.children[0]).upper(), node.children[1]


def _args(args_node):
    positional, named = [], {}
    for arg in args_node.children if args_node is not None else []:
        if isinstance(arg, Tree) and arg.data == "opt_arg":
            named[str(arg.children[0]).upper()] = arg.children[1]
        else:
            positional.append(arg)
    return positional, named


def _name(node) -> str | None:
    return str(node.children[0]).upper() if isinstance(node, Tree) and node.data == "var" else None


def field_checks(trees, max_tcp_mm_s: float | None, inputs: set[str] = frozenset()) -> list[Finding]:
    """The checks engineers of the field ask for: a wait on an input without \\MaxTime, a move with a tool or work
    object that has no value, a move with tool0 where the program has its own tool, a speed over the arm's."""
    declared, found = {}, []  # name -> (type, has an initial value, file, node)
    for file, tree in trees:
        for node in tree.iter_subtrees():
            if node.data == "data_decl":
                _l, _t, _s, type_name, name, _dims, init = node.children
                declared[str(name).upper()] = (str(type_name).upper(), init is not None, file, node, init, str(name))
    own_tools = sorted(entry[5] for entry in declared.values() if entry[0] == "TOOLDATA")
    wobj_use: dict[str, list] = {}
    for file, tree in trees:
        for node, name, args_node in _calls(tree):
            positional, named = _args(args_node)
            waits = name in ("WAITDI", "WAITUNTIL") and "MAXTIME" not in named and positional
            if waits and (name == "WAITDI" or _reads_input(positional[0], inputs)):
                what = "WaitDI" if name == "WAITDI" else "WaitUntil on an input"
                message = f"{what} without \\MaxTime waits for ever if the input never comes"
                found.append(_warning(file, node, "wait-without-timeout", message))
            if name in ("MOVEJ", "MOVEL", "MOVEC", "MOVEABSJ", "SEARCHL"):
                found += _move_checks(file, node, name, positional, named, declared, own_tools, wobj_use)
                found += _speed_checks(file, node, name, positional, named, declared, max_tcp_mm_s)
    for target, uses in wobj_use.items():
        if len({with_wobj for with_wobj, _place in uses}) > 1:
            file, node = next(place for with_wobj, place in uses if not with_wobj)
            shown = declared[target][5] if target in declared else target.lower()
            message = f"robtarget {shown} is moved to with and without \\WObj: in which frame was it taught?"
            found.append(_warning(file, node, "work-object", message))
    for name, (_kind, _init, file, node, _value, spelled) in declared.items():
        if name in PREDEFINED:
            found.append(_warning(file, node, "predefined", f"{spelled} is predefined data: the program's own "
                                  "declaration hides the system's (the controller refuses a second one)"))  # fmt: skip
    return found


def zero_divisors(trees) -> list[Finding]:
    """A division (/, DIV, MOD) by the literal 0: run stops there ("division by zero") when the line runs."""
    found = []
    for file, tree in trees:
        for node in tree.iter_subtrees_topdown():
            if node.data in ("div", "intdiv", "mod") and _number(node.children[-1]) == 0:
                warning = _warning(file, node, "division-by-zero", "division by zero")
                found.append(replace(warning, severity="error"))
    return found


def _string_constants(trees, decode) -> dict[str, int]:
    """The task's CONST strings by name -> their length, where the name is declared once and its value's length is
    known (a literal, or literals and such constants joined)."""
    decls: dict[str, list] = {}
    for _file, tree in trees:
        for node in tree.iter_subtrees():
            if node.data == "data_decl":
                decls.setdefault(str(node.children[4]).upper(), []).append(node)
    lengths: dict[str, int] = {}
    for _ in range(len(decls)):  # a constant made of constants declared after it: until nothing changes
        before = len(lengths)
        for name, nodes in decls.items():
            _l, _t, storage, type_name, _n, dims, init = nodes[0].children
            constant = len(nodes) == 1 and str(storage).upper() == "CONST" and str(type_name).upper() == "STRING"
            known = _least_length(init, decode, lengths) if constant and dims is None else None
            if known is not None:
                lengths[name] = known
        if len(lengths) == before:
            break
    return lengths


def _least_length(node, decode, constants: dict[str, int]) -> int | None:
    """The least length a string expression can have (literals, known constants, their joins; any other string
    part counted as empty), None where the expression is not known to be a string."""
    if not isinstance(node, Tree):
        return None
    if node.data == "string":
        return len(decode(str(node.children[0])))
    if node.data == "var":
        return constants.get(str(node.children[0]).upper())
    if node.data == "add":
        left, right = (_least_length(c, decode, constants) for c in node.children)
        return None if left is None and right is None else (left or 0) + (right or 0)
    return None


def long_strings(trees, decode) -> list[Finding]:
    """A joined string (+) longer than a string holds, by its literals and constants alone: run stops there (RAPID
    kernel technical reference manual, 3HAC050946-001, data type string: at most 80 characters); a literal that
    long is refused when the task is loaded."""
    constants = _string_constants(trees, decode)
    found = []
    for file, tree in trees:
        reported: set[int] = set()
        for node in tree.iter_subtrees_topdown():
            if node.data != "add" or id(node) in reported:
                continue
            chain = [node]  # the outermost join only: its parts joined in it are not reported again
            while chain:
                part = chain.pop()
                reported.add(id(part))
                chain.extend(c for c in part.children if isinstance(c, Tree) and c.data == "add")
            length = _least_length(node, decode, constants)
            if length is not None and length > STRING_MAX:
                message = f"a joined string of at least {length} characters: a string holds at most {STRING_MAX}"
                found.append(replace(_warning(file, node, "string-too-long", message), severity="error"))
    return found


def _literal_dims(node) -> tuple[int, ...] | None:
    """The whole-number literals of a dims or an index's subscripts, None where one is anything else."""
    if not isinstance(node, Tree) or not node.children:
        return None
    numbers = [_number(c) for c in node.children]
    if any(n is None or n != int(n) for n in numbers):
        return None
    return tuple(int(n) for n in numbers)


def _arrays(node) -> dict[str, tuple[int, ...] | None]:
    """The data a module or routine declares right in it (name -> its literal sizes, None: not such an array), and a
    routine's parameters (None: they hide the module's data of their name)."""
    out = {}
    for child in node.children:
        if isinstance(child, Tree) and child.data == "data_decl":
            out[str(child.children[4]).upper()] = _literal_dims(child.children[5])
        elif isinstance(child, Tree) and child.data == "body":
            out.update({k: v for k, v in _arrays(child).items() if k not in out})
    for param in node.iter_subtrees() if node.data in ("proc", "func") else ():
        if param.data in ("param", "opt_param"):
            out.setdefault(str(param.children[3]).upper(), None)
    return out


def constant_indexes(trees) -> list[Finding]:
    """An array read or written at literal subscripts beyond its declared size (RAPID arrays run from 1), or at a
    literal that is not a whole number: run stops there when the line runs; the size is known from the declaration."""
    shared = {}  # the modules' data: every routine of the task sees them (a LOCAL one its module's, names unique)
    for _file, tree in trees:
        for module in tree.iter_subtrees():
            if module.data == "module":
                shared.update(_arrays(module))
    found = []
    for file, tree in trees:
        for routine in (r for r in tree.iter_subtrees() if r.data in ("proc", "func", "trap")):
            own = _arrays(routine)
            for node in routine.iter_subtrees_topdown():
                if node.data != "index":
                    continue
                base, subscripts = node, []
                while isinstance(base, Tree) and base.data == "index":  # a{i, j} as the task holds it: (a{i}){j}
                    base, subscripts = base.children[0], [*base.children[1:], *subscripts]
                fraction = next((n for n in map(_number, subscripts) if n is not None and n != int(n)), None)
                if fraction is not None:
                    message = f"index {fraction:g} is not a whole number (an index must be one)"
                    found.append(replace(_warning(file, node, "index", message), severity="error"))
                    continue
                name = _name(base)
                dims = own[name] if name in own else shared.get(name)
                at = _literal_dims(Tree("subscripts", subscripts))
                if dims is None or at is None or len(at) != len(dims):
                    continue
                bad = next(((v, n) for v, n in zip(at, dims, strict=True) if not 1 <= v <= n), None)
                if bad is not None:
                    spelled = base.children[0]
                    message = f"index {bad[0]} out of range: {spelled} is declared with {bad[1]} elements (1..{bad[1]})"
                    found.append(replace(_warning(file, node, "index", message), severity="error"))
    return found


def _reads_input(cond, inputs: set[str]) -> bool:
    """A condition that reads an input signal (DInput, TestDI..., or an input signal's name as a value)."""
    for node in cond.iter_subtrees() if isinstance(cond, Tree) else ():
        if node.data == "call" and str(node.children[0]).upper() in INPUT_FUNCTIONS:
            return True
        if node.data == "var" and str(node.children[0]).upper() in inputs:
            return True
    return False


def _move_checks(file, node, name, positional, named, declared, own_tools, wobj_use) -> list[Finding]:
    found = []
    tool_index = 3 if name != "MOVEC" else 4
    tool_index = 4 if name == "SEARCHL" else tool_index
    tool = _name(positional[tool_index]) if len(positional) > tool_index else None
    if tool == "TOOL0" and own_tools and name != "MOVEABSJ":
        found.append(_warning(file, node, "tool", f"{node.children[0]} with tool0 (the flange) although the program "
                              f"declares its tool {own_tools[0]}: is the tool set for this move?"))  # fmt: skip
    for what, key in ((tool, "tool"), (_name(named.get("WOBJ")) if named.get("WOBJ") is not None else None, "wobj")):
        entry = declared.get(what) if what else None
        if entry is not None and not entry[1] and entry[0] in ("TOOLDATA", "WOBJDATA"):
            found.append(_warning(file, node, key, f"{entry[5]} is declared without a value: set the "
                                  f"{entry[0].lower()} before the move (its frame and load are zero)"))  # fmt: skip
    target_index = 1 if name in ("MOVEC", "SEARCHL") else 0
    target = _name(positional[target_index]) if len(positional) > target_index else None
    if target is not None and name != "MOVEABSJ":
        wobj_use.setdefault(target, []).append(("WOBJ" in named, (file, node)))
    return found


def _speed_checks(file, node, name, positional, named, declared, max_tcp_mm_s) -> list[Finding]:
    if max_tcp_mm_s is None:
        return []
    index = {"MOVEC": 2, "SEARCHL": 3}.get(name, 1)
    speed = positional[index] if len(positional) > index else None
    value = None
    if named.get("V") is not None:
        value = _number(named["V"])
    elif (upper := _name(speed)) is not None:
        if upper in PREDEFINED and PREDEFINED[upper].type == "SPEEDDATA":
            value = float(PREDEFINED[upper]["V_TCP"])
        elif upper in declared and declared[upper][4] is not None:
            value = _first_number(declared[upper][4])
    elif isinstance(speed, Tree) and speed.data == "aggregate":
        value = _first_number(speed)
    if value is not None and value > max_tcp_mm_s:
        message = f"{node.children[0]} at {value:g} mm/s: over the arm's {max_tcp_mm_s:g} mm/s"
        return [_warning(file, node, "speed", message)]
    return []


def _first_number(node) -> float | None:
    if isinstance(node, Tree) and node.data == "aggregate" and node.children:
        return _number(node.children[0])
    return None
