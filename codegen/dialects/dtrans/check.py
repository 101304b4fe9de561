"""`codegen check` of the Decompose/Trans dialect: what run stops on, found in the program's text before it runs."""

# What it reports ("error", each with file:line:column), beside the syntax and what loading refuses:
# - undefined-name: a variable no declaration and no parameter of the program names (run: undefined variable, or
#   assignment to undeclared variable);
# - undefined-routine: a Call or a function call of a name neither the program nor the interpreter defines;
# - arity: a call of the program's own Sub or Function with another number of arguments than its parameters;
# - index: an array read or written at a literal index outside 0..size-1 of its declaration, and a Decompose whose
#   literal start leaves fewer than the point's 6 elements;
# - division-by-zero: a division by the literal 0;
# - format: a TPWrite whose literal format has another number of fields than the arguments after it, or a field
#   wider than a message (interpreter.MESSAGE_MAX).

from __future__ import annotations

from lark import Token, Tree

from codegen.dialects.core.files import Finding, SourceFile, finding_of
from codegen.dialects.core.literals import literal_number as _number
from codegen.dialects.core.values import RunError
from codegen.dialects.dtrans.interpreter import BUILTINS, FORMAT_FIELD, MESSAGE_MAX, POINT_KEYS, load_tree, parse

ROUTINES = ("function", "sub")


def _start(node) -> tuple[int, int]:
    if isinstance(node, Token):
        return node.line or 0, node.column or 0
    meta = getattr(node, "meta", None)
    if meta is not None and not getattr(meta, "empty", True):
        return meta.line, meta.column
    for token in node.scan_values(lambda v: isinstance(v, Token)):
        return token.line or 0, token.column or 0
    return 0, 0


def _decls(statements) -> dict[str, int | None]:
    """The variables declared in these statements (in their blocks too): name -> the array's size, None: not an
    array, or declared twice with other sizes."""
    out: dict[str, int | None] = {}
    for statement in (s for s in statements if isinstance(s, Tree)):
        for node in statement.iter_subtrees_topdown():
            if node.data == "decl":
                _type, name, size, _init = node.children
                value = int(str(size)) if size is not None else None
                out[str(name)] = value if out.get(str(name), value) == value else None
    return out


class Checker:
    """The checks of one program file's tree."""

    def __init__(self, tree: Tree, filename: str) -> None:
        self.tree, self.filename = tree, filename
        self.findings: list[Finding] = []
        self.routines = {}  # name -> its parameters' count
        for node in tree.children:
            if isinstance(node, Tree) and node.data in ROUTINES:
                params = node.children[2 if node.data == "function" else 1]
                name = node.children[1 if node.data == "function" else 0]
                self.routines[str(name)] = len(params.children) if params is not None else 0

    def add(self, node, code: str, message: str) -> None:
        line, column = _start(node)
        self.findings.append(Finding(self.filename, line, column, "error", code, message))

    def run(self) -> list[Finding]:
        self.names()
        self.calls()
        self.indexes()
        self.divisions()
        self.formats()
        return sorted(self.findings, key=lambda f: (f.line, f.column))

    def names(self) -> None:
        declared = {str(n.children[1]) for n in self.tree.iter_subtrees() if n.data in ("decl", "param")}
        reported = set()
        for node in self.tree.iter_subtrees_topdown():
            if node.data == "var" and str(node.children[0]) not in declared | reported:
                reported.add(str(node.children[0]))
                self.add(node, "undefined-name", f"undefined variable {node.children[0]}: no declaration names it")

    def calls(self) -> None:
        for node in self.tree.iter_subtrees_topdown():
            if node.data not in ("call_stmt", "call"):
                continue
            name, args = str(node.children[0]), node.children[1]
            count = len(args.children) if args is not None else 0
            if name in self.routines and count != self.routines[name]:
                self.add(node, "arity", f"{name} takes {self.routines[name]} arguments, got {count}")
            elif name not in self.routines and name not in BUILTINS:
                self.add(node, "undefined-routine", f"unknown routine {name}: neither the program nor the "
                         "interpreter defines it")  # fmt: skip

    def _scopes(self):
        """(the statements of a scope, the arrays it sees: name -> size, None: not an array or of unknown size)."""
        top = [c for c in self.tree.children if isinstance(c, Tree) and c.data not in ROUTINES]
        shared = _decls(top)
        yield top, shared
        for routine in (c for c in self.tree.children if isinstance(c, Tree) and c.data in ROUTINES):
            params = routine.children[2 if routine.data == "function" else 1]
            own = {str(p.children[1]): None for p in (params.children if params is not None else [])}
            body = routine.children[-1].children
            yield body, {**shared, **own, **_decls(body)}

    def indexes(self) -> None:
        for statements, sizes in self._scopes():
            for statement in (s for s in statements if isinstance(s, Tree)):
                for node in statement.iter_subtrees_topdown():
                    if node.data == "decompose":
                        self._decompose(node, sizes)
                    elif node.data == "index":
                        self._index(node, sizes)

    def _array(self, node, sizes) -> tuple[str, int, float] | None:
        base, at = node.children[0], _number(node.children[1])
        if not (isinstance(base, Tree) and base.data == "var") or at is None or at != int(at):
            return None
        size = sizes.get(str(base.children[0]))
        return None if size is None else (str(base.children[0]), size, at)

    def _index(self, node, sizes) -> None:
        known = self._array(node, sizes)
        if known is not None and not 0 <= known[2] < known[1]:
            name, size, at = known
            self.add(node, "index", f"index {int(at)} out of range 0..{size - 1}: {name} is declared with {size}")

    def _decompose(self, node, sizes) -> None:
        target = node.children[0]
        known = self._array(target, sizes) if isinstance(target, Tree) and target.data == "index" else None
        if known is not None and not 0 <= known[2] <= known[1] - len(POINT_KEYS):
            name, size, at = known
            self.add(node, "index", f"Decompose needs {len(POINT_KEYS)} elements from index {int(at)}: {name} is "
                     f"declared with {size}")  # fmt: skip

    def divisions(self) -> None:
        for node in self.tree.iter_subtrees_topdown():
            if node.data == "div" and _number(node.children[1]) == 0:
                self.add(node, "division-by-zero", "division by zero")

    def formats(self) -> None:
        for node in self.tree.iter_subtrees_topdown():
            if node.data != "tpwrite_stmt":
                continue
            _channel, fmt, *args = node.children
            if not (isinstance(fmt, Tree) and fmt.data == "string"):
                continue
            fields = [m for m in FORMAT_FIELD.finditer(str(fmt.children[0])[1:-1]) if m.group(3) != "%"]
            wide = [m.group(0) for m in fields if any(g and abs(int(g)) > MESSAGE_MAX for g in m.groups()[:2])]
            if wide:
                self.add(node, "format", f"format field {wide[0]!r} is wider than a message ({MESSAGE_MAX} characters)")
            elif len(fields) != len(args):
                self.add(node, "format", f"the format has {len(fields)} fields and {len(args)} arguments follow it")


def check_file(source: SourceFile) -> list[Finding]:
    """Every finding of one program file, its text parsed once: its syntax error, else what loading refuses and
    what the checks above find (a check's finding on a line loading already reported left out)."""
    try:
        tree = parse(source.text, source.name)
    except RunError as exc:
        return [finding_of(exc, [source], "syntax")]
    except RecursionError:
        return [finding_of(f"{source.name}: statements or expressions nested too deeply", [source], "syntax")]
    loading = []
    try:
        load_tree(tree, source.name)
    except RunError as exc:
        loading.append(finding_of(exc, [source]))
    except RecursionError:
        loading.append(finding_of(f"{source.name}: statements or expressions nested too deeply", [source]))
    lines = {(f.file, f.line) for f in loading}
    return loading + [f for f in Checker(tree, source.name).run() if (f.file, f.line) not in lines]
