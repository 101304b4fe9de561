"""A RAPID task of several modules: names by scope (global, LOCAL), RECORD and ALIAS types, data, routines, main."""

from __future__ import annotations

import copy
import re

from lark import Token, Tree

from codegen.dialects.core.files import Finding, SourceFile
from codegen.dialects.core.kept import STORE
from codegen.dialects.core.program import Program
from codegen.dialects.core.values import RunError
from codegen.dialects.rapid import signals
from codegen.dialects.rapid.compiler import RAPIDCompiler, Skip, parse
from codegen.dialects.rapid.predefined import USER_DATA
from codegen.dialects.rapid.types import IDENTIFIER_MAX

# A task's program (ABB, "Technical reference manual - RAPID overview", Program structure; as recalled): the
# modules loaded in a task (program modules .mod, system modules .sys) make one program; exactly one of them has
# the entry routine main. Module attributes SYSMODULE, NOSTEPIN, VIEWONLY, READONLY and NOVIEW change how the
# FlexPendant shows and steps a module, not what it does: accepted, no effect here.
MODULE_ATTRIBUTES = {"SYSMODULE", "NOSTEPIN", "VIEWONLY", "READONLY", "NOVIEW"}
_WHERE = re.compile(r"^(?P<file>.*?):(?P<line>\d+):(?P<column>\d+): (?P<message>.*)$", re.DOTALL)


_MULTI_INDEX = re.compile(r"\{[^}\n]*,")  # a{i, j} somewhere (or a declaration's {2, 3}): index trees to nest


def _nest_indexes(tree) -> None:
    """a{i, j} as (a{i}){j}: the compiler reads and stores elements of nested arrays one index at a time."""
    for node in tree.iter_subtrees():
        while node.data == "index" and len(node.children) > 2:
            base, first, *rest = node.children
            node.children = [Tree("index", [base, first], node.meta), *rest]


class _Symbol:
    __slots__ = ("kind", "local", "module", "name", "node")

    def __init__(self, kind: str, name: Token, local: bool, module: str, node) -> None:
        self.kind, self.name, self.local, self.module, self.node = kind, name, local, module, node


def _item_symbol(item, module: str) -> _Symbol | None:
    c = item.children
    local = isinstance(c[0], Token) and c[0].type == "LOCAL"
    if item.data == "data_decl":
        return _Symbol("data", c[4], local, module, item)
    if item.data == "func":
        return _Symbol("func", c[2], local, module, item)
    if item.data in ("proc", "trap"):
        return _Symbol(item.data, c[1], local, module, item)
    if item.data == "record_decl":
        return _Symbol("record", c[1], local, module, item)
    if item.data == "alias_decl":
        return _Symbol("alias", c[2], local, module, item)
    return None


def _guard(compiler, fn, *args):
    """Run one compile step; in `codegen check` a reported construct is skipped and the next one goes on."""
    try:
        return fn(*args)
    except Skip:
        return None


def _long_names(compiler: RAPIDCompiler, tree) -> None:
    """Names longer than the controller takes, each once (where it is first written)."""
    seen = set()
    for token in tree.scan_values(lambda v: isinstance(v, Token) and v.type == "NAME" and len(v) > IDENTIFIER_MAX):
        if token.upper() not in seen:
            seen.add(token.upper())
            compiler.report(token, f"name {token} has {len(token)} characters: at most {IDENTIFIER_MAX}", "name-length")


def load_task(
    files: list[SourceFile], findings: list | None = None, out: dict | None = None, entry: str | None = None
) -> Program | None:
    """The program of a task's modules (their files in any order; one of them has PROC main, or the run starts at
    entry: a global PROC without parameters, as after PP to Routine). findings: `codegen check` collects every
    finding there and gets None back when one is an error; else the first error raises."""
    modules, trees = [], []  # (file name, module tree), (file name, file tree)
    for f in files:
        tree = parse(f.text, f.name)
        if _MULTI_INDEX.search(f.text):
            if STORE.shares:  # the parse store's tree: nested on a copy of its own
                tree = copy.deepcopy(tree)
            _nest_indexes(tree)
        trees.append((f.name, tree))
        modules += [(f.name, m) for m in tree.children if isinstance(m, Tree) and m.data == "module"]
    if out is not None:
        out["trees"] = trees
    compiler = RAPIDCompiler(files[0].name, findings)
    if out is not None:  # `codegen check` reads the compiler's tables even when the task does not load
        out["compiler"] = compiler
    symbols, by_module = _symbols(compiler, modules)
    _types(compiler, symbols)
    _keys(compiler, symbols, by_module)
    compiler.scopes = {module: entry["scope"] for (module, _file), entry in by_module.items()}
    data = _user_data(compiler, files)
    _signals(compiler, modules)
    for module, file in by_module:
        _enter(compiler, module, file, by_module)
        for symbol in by_module[(module, file)]["symbols"]:
            if symbol.kind in ("proc", "func", "trap"):
                _guard(compiler, _declare_routine, compiler, symbol)
    for module, file in by_module:
        _enter(compiler, module, file, by_module)
        for symbol in by_module[(module, file)]["symbols"]:
            if symbol.kind == "data":
                key = compiler.data_key(str(symbol.name))
                compiler.module_data.setdefault(module, {})[str(symbol.name).upper()] = key
                made = _guard(compiler, compiler.decl, symbol.node, key)
                if made is not None:
                    data.append(made)
    for module, file in by_module:
        _enter(compiler, module, file, by_module)
        for symbol in by_module[(module, file)]["symbols"]:
            if symbol.kind in ("proc", "func", "trap"):
                key = compiler.data_key(str(symbol.name))
                if key in compiler.routine_decls:
                    _guard(compiler, compiler.routine, symbol.node, key)
                if symbol.kind == "trap" and key in compiler.routines:
                    compiler.traps[key] = compiler.routines.pop(key)
    compiler.scope = {}
    main = _main(compiler, symbols, files) if entry is None else _entry(compiler, symbols, files, entry)
    if findings is not None and any(f.severity != "warning" for f in findings):
        return None
    program = Program(main[1] if main else "", compiler, _initialiser(data), main[0] if main else None)
    try:
        program.unknown_inputs(())  # the module data now: an error in an initial value is a load error
    except RunError as exc:
        if findings is None:
            raise
        match = _WHERE.match(str(exc))
        if match:
            file, line, column = match["file"], int(match["line"]), int(match["column"])
        else:
            file, line, column = files[0].name, 0, 0
        compiler.filename = file
        findings.append(compiler_finding(file, line, column, match["message"] if match else str(exc)))
        return None
    return program


def compiler_finding(file: str, line: int, column: int, message: str) -> Finding:
    return Finding(file, line, column, "error", "error", message)


def _symbols(compiler: RAPIDCompiler, modules):
    """Every module's declarations, in order; a module named twice, or a name declared twice in one module, fails."""
    symbols, by_module, names = [], {}, {}
    for file, module in modules:
        compiler.filename = file
        name_token, attrs = module.children[0], module.children[1]
        _long_names(compiler, module)
        key = str(name_token).upper()
        if key in names:
            compiler.report(name_token, f"module {name_token} is also in {names[key]}", "duplicate")
            continue
        names[key] = file
        for attr in attrs.children if attrs is not None else []:
            if str(attr).upper() not in MODULE_ATTRIBUTES:
                compiler.report(attr, f"module attribute {attr} is not one RAPID knows", "module-attribute")
        mine, seen = [], {}
        for item in module.children[2:]:
            symbol = _item_symbol(item, key) if isinstance(item, Tree) else None
            if symbol is None:
                continue
            upper = str(symbol.name).upper()
            if upper in seen:
                compiler.report(symbol.node, _twice(seen[upper], symbol), "duplicate")
                continue
            seen[upper] = symbol
            mine.append(symbol)
        symbols += mine
        by_module[(key, file)] = {"symbols": mine, "scope": {}}
    return symbols, by_module


def _twice(first: _Symbol, second: _Symbol) -> str:
    routines = ("proc", "func", "trap")
    if first.kind in routines and second.kind in routines:
        return f"routine {second.name} defined twice"
    if first.kind == second.kind:
        return f"{second.name} declared twice in the module (names ignore case)"
    return f"{second.name} names both data and a routine (names ignore case)"  # one name, one object in a scope


def _types(compiler: RAPIDCompiler, symbols) -> None:
    """RECORD and ALIAS types of the task (one namespace for types), their components' types resolved."""
    for symbol in symbols:
        if symbol.kind == "alias":
            compiler.aliases[str(symbol.name).upper()] = str(symbol.node.children[1]).upper()
        elif symbol.kind == "record":
            compiler.records[str(symbol.name).upper()] = []
    for symbol in symbols:
        if symbol.kind == "record":
            fields = []
            for field in symbol.node.children[2:]:
                ftype, fname = field.children
                resolved = _guard(compiler, compiler.resolve_type, ftype)
                fields.append((str(fname).upper(), resolved or "NUM"))
            compiler.records[str(symbol.name).upper()] = fields
        elif symbol.kind == "alias":
            _guard(compiler, compiler.resolve_type, symbol.node.children[1])
    compiler.RECORD_TYPES = frozenset(compiler.records)


def _keys(compiler: RAPIDCompiler, symbols, by_module) -> None:
    """Each datum's and routine's key: its name, or name@module for a LOCAL one whose name another module also
    declares; a global name declared in two modules fails."""
    declared: dict[str, list[_Symbol]] = {}
    for symbol in symbols:
        if symbol.kind not in ("record", "alias"):
            declared.setdefault(str(symbol.name).upper(), []).append(symbol)
    for upper, group in declared.items():
        public = [s for s in group if not s.local]
        if len(public) > 1:
            first, second = public[0], public[1]
            compiler.filename = _file_of(by_module, second)
            compiler.report(second.name, f"{second.name} is declared in modules {first.module} and {second.module}: "
                            "a global name is declared once in a task", "duplicate")  # fmt: skip
        for symbol in group:
            if symbol.local and len(group) > 1:
                key = f"{upper}@{symbol.module}"
                by_module[(symbol.module, _file_of(by_module, symbol))]["scope"][upper] = key
            elif symbol.local:
                compiler.local_owner[upper] = symbol.module
    for (module, file), entry in by_module.items():
        compiler.filename, compiler.scope, compiler.module_name = file, entry["scope"], module
        for symbol in entry["symbols"]:
            key = compiler.data_key(str(symbol.name))
            if symbol.kind == "data":
                node = symbol.node
                compiler.storage[key] = str(node.children[2]).upper()
                static = _guard(compiler, compiler.static_type, node)
                if static is None:  # an array whose size is computed: its element type, size unknown
                    base = _guard(compiler, compiler.resolve_type, node.children[3]) or "NUM"
                    dims = node.children[5]
                    static = base
                    for _ in dims.children if dims is not None else []:
                        static = (static, None)
                compiler.data_types[key] = static
            elif symbol.kind in ("proc", "func"):
                compiler.user_routines.add(key)
            elif symbol.kind == "trap":
                compiler.trap_names.add(key)


def _enter(compiler: RAPIDCompiler, module: str, file: str, by_module) -> None:
    compiler.filename, compiler.scope, compiler.module_name = file, by_module[(module, file)]["scope"], module


_USER_NAMES = re.compile(r"\b(reg[1-5]|clock1)\b", re.IGNORECASE)


def _user_data(compiler: RAPIDCompiler, files) -> list:
    """The USER module's variables (reg1..reg5, clock1) the program uses without declaring them itself."""
    used = {m.upper() for f in files for m in _USER_NAMES.findall(f.text)}
    data = []
    for name, kind in USER_DATA.items():
        if name in used and name not in compiler.data_types:
            compiler.data_types[name], compiler.storage[name] = kind, "VAR"
            data.append((name, lambda fr, kind=kind: (kind, compiler.zero_of(kind))))
    return data


def _file_of(by_module, symbol) -> str:
    return next(file for (module, file), entry in by_module.items() if symbol in entry["symbols"])


def _signals(compiler: RAPIDCompiler, modules) -> None:
    """The signals the program names in signal instructions and functions without declaring them (simulated I/O)."""
    for file, module in modules:
        compiler.filename = file
        for name, kind, token in signals.signal_uses(module):
            upper = name.upper()
            if upper in compiler.data_types or any(k.startswith(upper + "@") for k in compiler.data_types):
                continue
            known = compiler.signal_kinds.get(upper)
            if known is None:
                compiler.signal_names[upper], compiler.signal_kinds[upper] = name, kind
            elif known != kind:
                shown = f"{signals.KIND_NAMES[known]} and as a {signals.KIND_NAMES[kind]}"
                compiler.report(token, f"signal {name} is used as a {shown}", "signal-kind", "warning")


def _declare_routine(compiler: RAPIDCompiler, symbol) -> None:
    node = symbol.node
    key = compiler.data_key(str(symbol.name))
    params = node.children[3] if symbol.kind == "func" else (node.children[2] if symbol.kind == "proc" else None)
    required, spec = compiler.parameters(params if isinstance(params, Tree) and params.data == "params" else None)
    compiler.routine_decls[key] = (required, spec, symbol.kind == "func")


def _entry(compiler: RAPIDCompiler, symbols, files, entry: str) -> tuple[str, str]:
    """PP to Routine (ABB, "Operating manual - IRC5 with FlexPendant", as recalled: the program pointer set to a
    routine without parameters, the program started there): the global PROC entry."""
    found = [s for s in symbols if s.kind == "proc" and not s.local and str(s.name).upper() == entry.upper()]
    key = compiler.data_key(entry)
    if not found or key not in compiler.routines or compiler.routine_decls[key][0]:
        names = ", ".join(f.name for f in files)
        raise RunError(f"{names}: no global PROC {entry} without parameters to start at")
    return key, str(found[0].module)


def _main(compiler: RAPIDCompiler, symbols, files) -> tuple[str, str] | None:
    mains = [s for s in symbols if s.kind == "proc" and str(s.name).upper() == "MAIN"]
    names = ", ".join(f.name for f in files)
    if not mains:
        message = f"{names}: no PROC main" + (" in the task's modules" if len(files) > 1 else "")
        if compiler.findings is None:
            raise RunError(message)
        # `codegen check`: modules without main are loaded into a task whose main calls them
        text = message.split(": ", 1)[1] + " (modules another task's main calls: load them there)"
        compiler.findings.append(Finding(files[0].name, 0, 0, "warning", "no-main", text))
        return None
    local = (k for k in compiler.routines if k.startswith("MAIN@"))
    key = "MAIN" if "MAIN" in compiler.routines else next(local, "MAIN")
    return key, str(mains[0].module)


def _initialiser(data):
    """The module data's initial values, in the modules' order; one that reads data declared later (in its
    module or another) is tried again once the others have their values."""

    def init(fr):
        pending = list(data)
        while pending:
            failed = []
            for entry in pending:
                key, make = entry
                try:
                    type_name, value = make(fr)
                except RunError as exc:
                    if type(exc) is not RunError or "undefined variable" not in str(exc):
                        raise
                    failed.append((entry, exc))
                    continue
                fr.m.global_types[key] = type_name
                fr.m.globals[key] = value
            if len(failed) == len(pending):
                raise failed[0][1]
            pending = [entry for entry, _exc in failed]

    return init
