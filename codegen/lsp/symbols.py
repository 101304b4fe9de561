"""The names a program declares and uses, across its files: the outline, go to definition, find references."""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

from lark import Token, Tree
from lsprotocol import types

from codegen.dialects import Dialect
from codegen.dialects.core.values import RunError
from codegen.lsp.documents import Program

K = types.SymbolKind
# A declaring grammar rule -> its symbol kind and which of its NAME tokens is the declared name (the ones before it
# being types); an INT child names an interrupt by its number. Rules of every language's grammar, by rule name.
DECLARES: dict[str, tuple[K, int]] = {
    "def_routine": (K.Function, 0),
    "def_function": (K.Function, 1),
    "defdat": (K.Module, 0),
    "decl_item": (K.Variable, 0),
    "signal_decl": (K.Variable, 0),
    "enum_decl": (K.Enum, 0),
    "struc_decl": (K.Struct, 0),
    "interrupt_decl": (K.Event, -1),
    "module": (K.Module, 0),
    "data_decl": (K.Variable, 1),
    "proc": (K.Function, 0),
    "func": (K.Function, 1),
    "trap": (K.Event, 0),
    "record_decl": (K.Struct, 0),
    "alias_decl": (K.Class, 1),
    "funcdef": (K.Function, 0),
    "threaddef": (K.Event, 0),
    "secdef": (K.Function, 0),
    "global_stmt": (K.Variable, 0),
}
ASSIGN, PLAIN_NAME = "assign", "var"  # an assignment's rule and its target's when the target is a name alone
CONTAINERS = frozenset({"def_routine", "def_function", "proc", "func", "trap", "funcdef", "threaddef", "secdef"})
OUTLINE = (frozenset(DECLARES) | {ASSIGN}) - {"module", "defdat"}  # the file itself is the module


@dataclass(frozen=True)
class Symbol:
    name: str
    kind: K
    file: str
    line: int  # 1-based, as lark counts
    column: int  # 1-based
    rule: str
    top: bool  # declared at module level (not inside a routine)

    def range(self) -> types.Range:
        start = types.Position(self.line - 1, self.column - 1)
        return types.Range(start, types.Position(self.line - 1, self.column - 1 + len(self.name)))


@dataclass(frozen=True)
class Index:
    """One file's declarations, its assignments to plain names (a language without declarations, URScript, makes
    a variable by assigning it) and its name tokens (name, line, column), from its parse tree."""

    symbols: tuple[Symbol, ...]
    assigned: tuple[Symbol, ...]
    uses: tuple[tuple[str, int, int], ...]


def caseless(dialect: type[Dialect]) -> bool:
    """Whether the language ignores the case of names (its grammar's NAME terminal reads keywords caselessly)."""
    return "(?i:" in (dialect.terminal("NAME") or "")


def folded(dialect: type[Dialect], name: str) -> str:
    return name.upper() if caseless(dialect) else name


@lru_cache(maxsize=64)
def index_of(dialect: type[Dialect], name: str, text: str) -> Index | None:
    """The declarations and uses of names of one file; None when it does not parse."""
    try:
        tree = dialect.parse(text, name, positions=False)
    except (RunError, RecursionError):
        return None
    symbols: list[Symbol] = []
    assigned: list[Symbol] = []
    _walk(tree, name, symbols, assigned, top=True)
    uses = tuple(
        (str(t), t.line, t.column) for t in tree.scan_values(lambda v: isinstance(v, Token) and v.type == "NAME")
    )
    return Index(tuple(symbols), tuple(assigned), uses)


def _walk(tree: Tree, file: str, out: list[Symbol], assigned: list[Symbol], top: bool) -> None:
    own = DECLARES.get(tree.data)
    if own is not None:
        kind, which = own
        token = _name_token(tree, which)
        if token is not None:
            out.append(Symbol(str(token), kind, file, token.line, token.column, tree.data, top))
    target = tree.children[0] if tree.data == ASSIGN and tree.children else None
    if isinstance(target, Tree) and target.data == PLAIN_NAME and isinstance(target.children[0], Token):
        token = target.children[0]
        assigned.append(Symbol(str(token), K.Variable, file, token.line, token.column, tree.data, top))
    inside = top and tree.data not in CONTAINERS
    for child in tree.children:
        if isinstance(child, Tree):
            _walk(child, file, out, assigned, inside)


def _name_token(tree: Tree, which: int) -> Token | None:
    if which < 0:  # an interrupt: by its number
        return next((c for c in tree.children if isinstance(c, Token) and c.type == "INT"), None)
    names = [c for c in tree.children if isinstance(c, Token) and c.type == "NAME"]
    return names[which] if which < len(names) else None


def program_symbols(program: Program) -> list[Symbol]:
    """The program's declarations, and the first assignment of each name it assigns without declaring it."""
    out: list[Symbol] = []
    assigned: list[Symbol] = []
    for f in program.files:
        index = index_of(program.dialect, f.name, f.text)
        if index is not None:
            out.extend(index.symbols)
            assigned.extend(index.assigned)
    declared = {folded(program.dialect, s.name) for s in out}
    controllers = program.dialect.predefined()
    for symbol in assigned:
        key = folded(program.dialect, symbol.name)
        # a controller's own name (predefined, or a system variable's sigil such as $) is not the program's
        if key not in declared and key not in controllers and (symbol.name[:1].isalpha() or symbol.name[:1] == "_"):
            declared.add(key)
            out.append(symbol)
    return out


def word_at(text: str, line: int, character: int) -> tuple[str, int] | None:
    """The name under a 0-based position and its 0-based start column, or None."""
    lines = text.split("\n")
    if line >= len(lines):
        return None
    content = lines[line]
    start = character
    while start > 0 and (content[start - 1].isalnum() or content[start - 1] in "_$"):
        start -= 1
    end = character
    while end < len(content) and (content[end].isalnum() or content[end] in "_$"):
        end += 1
    return (content[start:end], start) if end > start else None


def definitions(program: Program, name: str) -> list[Symbol]:
    """Where a name is declared in the program: a module-level declaration first (a routine's own local of that
    name would shadow it only inside the routine; both are offered)."""
    key = folded(program.dialect, name)
    found = [s for s in program_symbols(program) if folded(program.dialect, s.name) == key]
    return sorted(found, key=lambda s: (not s.top, s.file, s.line))


def references(program: Program, name: str) -> list[tuple[str, int, int]]:
    """Every use of a name in the program's files, as (file, line, column), 1-based."""
    key = folded(program.dialect, name)
    out = []
    for f in program.files:
        index = index_of(program.dialect, f.name, f.text)
        if index is not None:
            out += [(f.name, line, column) for n, line, column in index.uses if folded(program.dialect, n) == key]
    return out


def outline(program: Program, file: str) -> list[types.DocumentSymbol]:
    """The outline of one file: its routines (with the data declared in them), module-level data and interrupts."""
    shown = [s for s in program_symbols(program) if s.file == file and s.rule in OUTLINE]
    routines = [s for s in shown if s.rule in CONTAINERS]
    out: list[types.DocumentSymbol] = []
    lines = (program.text_of(file) or "").split("\n")
    ends = _routine_ends(routines, lines)
    for symbol in shown:
        if symbol.top or symbol.rule in CONTAINERS:
            item = _document_symbol(symbol, ends.get(symbol, symbol.line), lines)
            out.append(item)
    for symbol in shown:
        if not symbol.top and symbol.rule not in CONTAINERS:
            owner = next((r for r in routines if r.line <= symbol.line <= ends.get(r, r.line)), None)
            parent = next((d for d in out if owner is not None and d.selection_range == owner.range()), None)
            if parent is not None:
                parent.children = [*(parent.children or []), _document_symbol(symbol, symbol.line, lines)]
    return out


def _routine_ends(routines: list[Symbol], lines: list[str]) -> dict[Symbol, int]:
    """Each routine's last line: the line before the next routine's (or the file's end), its trailing blanks cut."""
    ends = {}
    ordered = sorted(routines, key=lambda s: s.line)
    for i, symbol in enumerate(ordered):
        end = ordered[i + 1].line - 1 if i + 1 < len(ordered) else len(lines)
        while end > symbol.line and not lines[end - 1].strip():
            end -= 1
        ends[symbol] = end
    return ends


def _document_symbol(symbol: Symbol, end: int, lines: list[str]) -> types.DocumentSymbol:
    last = lines[end - 1] if 0 < end <= len(lines) else ""
    whole = types.Range(types.Position(symbol.line - 1, 0), types.Position(end - 1, len(last)))
    detail = lines[symbol.line - 1].strip() if symbol.line <= len(lines) else ""
    name = f"INTERRUPT {symbol.name}" if symbol.rule == "interrupt_decl" else symbol.name
    return types.DocumentSymbol(
        name=name, kind=symbol.kind, range=whole, selection_range=symbol.range(), detail=detail[:120]
    )
