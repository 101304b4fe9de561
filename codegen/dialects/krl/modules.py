"""KRL programs of several files: modules (.src with .dat), which files make one program, and linking them."""

from __future__ import annotations

import copy
import re
from collections import ChainMap
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path

from lark import Token, Tree

from codegen.dialects.core.files import SourceFile, read_source
from codegen.dialects.core.program import Program
from codegen.dialects.core.shapes import ShapeCache
from codegen.dialects.core.values import RunError
from codegen.dialects.krl import KRL, eki
from codegen.dialects.krl.compiler import KRLCompiler
from codegen.dialects.krl.environment import CONFIG_DAT, is_config
from codegen.dialects.krl.environment import NAME as CONFIG_NAME
from codegen.dialects.krl.names import Scope
from codegen.dialects.krl.numbered import SYSTEM_ARRAYS
from codegen.dialects.krl.syntax import parse

# A program is its module (the program file, a .src, with its .dat) and the modules it may call: on the
# controller every module's global routines and data are there (see codegen/dialects/krl/names.py for the
# scope rules), so a program of several files is all of them. Which of the given .src files are programs:
# those whose main routine no other given module calls (a module called by another is a library). A .dat
# alone is a module of data (a PUBLIC data list of global names); $config.dat is the controller's (it
# replaces the interpreter's built-in one: codegen/dialects/krl/environment.py).


@dataclass
class Module:
    name: str  # upper-case stem, e.g. CELL
    src: SourceFile | None = None
    dat: SourceFile | None = None
    trees: list = field(default_factory=list)  # (file, parse tree)
    config: bool = False


def group_modules(files: list[SourceFile], first_is_program: bool = False) -> tuple[list[Module], list[SourceFile]]:
    """The modules of the given files in their order, and the $config.dat files among them (first_is_program:
    the first file is a program file whatever its name)."""
    modules: dict[str, Module] = {}
    configs = []
    for i, f in enumerate(files):
        if is_config(f.name):
            configs.append(f)
            continue
        if f.suffix == eki.SUFFIX:  # a channel's configuration (the program's EKI_Init reads it), no module
            continue
        module = modules.setdefault(f.stem.upper(), Module(f.stem.upper()))
        if f.suffix in KRL.suffixes or (first_is_program and i == 0):
            if module.src is not None:
                raise RunError(f"{f.name}: a second module {module.name} (also {module.src.name})")
            module.src = f
        else:
            if module.dat is not None:
                raise RunError(f"{f.name}: a second data list {module.name} (also {module.dat.name})")
            module.dat = f
    return list(modules.values()), configs


def _calls(tree) -> set[str]:
    """The routines a module calls: by name, and those its interrupts call (INTERRUPT DECL ... DO name())."""
    called = set()
    for sub in tree.iter_subtrees():
        if sub.data in ("call", "call_stmt") and isinstance(sub.children[0], Token):
            called.add(str(sub.children[0]).upper())
        elif sub.data == "interrupt_decl":
            called.update(str(c).upper() for c in sub.children if isinstance(c, Token) and c.type == "NAME")
    return called


def _callable(module: Module, tree) -> set[str]:
    """What other modules may call of a module: its main routine (named like it) and its GLOBAL ones."""
    names = {module.name}
    for i, node in enumerate(_routines(tree)):
        if i == 0 or node.children[0] is not None:
            names.add(routine_name(node))
    return names


def programs(files: list[SourceFile]) -> list[list[SourceFile]]:
    """Which files make one program each, the program file first: each .src none of whose routines another
    module calls, with its .dat, the modules others call (libraries), the data lists without a .src and
    $config.dat. Where a .src does not parse, which module calls which is not known: the files are one program,
    that file first (loading it names its syntax error's line, check reports every file's findings)."""
    modules, configs = group_modules(files)
    with_src = [m for m in modules if m.src is not None]
    if not with_src:
        own = ", ".join(KRL.suffixes)
        said = f"{files[0].name}: no program file ({own}) among the files: a data list is read with its program"
        raise RunError(said)
    calls, offers = {}, {}
    for module in with_src:
        try:
            tree = parse(module.src.text, module.src.name, positions=False)
        except RunError:
            rest = [f for m in modules if m is not module for f in (m.src, m.dat) if f is not None]
            return [[module.src, *([module.dat] if module.dat else []), *rest, *configs]]
        offers[module.name] = _callable(module, tree)
        calls[module.name] = _calls(tree) - offers[module.name]
    libraries = {
        name
        for name, offered in offers.items()
        if any(offered & called for other, called in calls.items() if other != name)
    }
    mains = [m for m in with_src if m.name not in libraries] or with_src[:1]
    shared = [m for m in modules if m.src is None or m.name in libraries or m not in mains]  # libraries, data
    channels = [f for f in files if f.suffix == eki.SUFFIX]  # every program may open each channel
    out = []
    for main in mains:
        rest = [f for m in shared if m is not main for f in (m.src, m.dat) if f is not None]
        out.append([main.src, *([main.dat] if main.dat else []), *rest, *configs, *channels])
    return out


_WORD = re.compile(r"[A-Za-z_$][A-Za-z0-9_$]*")


def data_lists_beside(path: Path, encodings) -> list[Path]:
    """The data lists in the folder of a .src that the program uses (data_lists_used), as paths."""
    folder = path.parent
    stems = {p.stem.upper() for p in folder.iterdir() if p.suffix.lower() in KRL.suffixes}
    program = read_source(path, encodings)
    candidates = {
        p: read_source(p, encodings)
        for p in sorted(folder.iterdir())
        if p.suffix.lower() == ".dat" and p.stem.upper() not in stems and not is_config(p.name)
    }
    chosen = {f.name for f in data_lists_used(program, list(candidates.values()))}
    return [p for p, data in candidates.items() if data.name in chosen]


def data_lists_used(program: SourceFile, files: list[SourceFile]) -> list[SourceFile]:
    """The data lists among the files of a program's folder that it is linked with: each .dat without a .src of its
    own among them (not $config.dat) that declares a name the program's text uses, as the controller makes the
    GLOBAL data of every PUBLIC data list of its program folder known to every module (the pallet's count files);
    one that does not parse comes too (loading names its line)."""
    stems = {f.stem.upper() for f in [program, *files] if f.suffix in KRL.suffixes}
    used = {w.upper() for w in _WORD.findall(program.text)}
    out = []
    for data in files:
        if data.suffix != ".dat" or data.stem.upper() in stems or is_config(data.name):
            continue
        try:
            _types, declared = _declared([(data.name, parse(data.text, data.name, positions=False))])
        except RunError:
            out.append(data)
            continue
        if declared & used:
            out.append(data)
    return out


@cache
def _builtin_config():
    return parse(CONFIG_DAT, CONFIG_NAME)


def _declared(trees: list) -> tuple[set[str], set[str]]:
    """The types (ENUM, STRUC) and the data names (DECL, SIGNAL) some data lists declare."""
    types, data = set(), set()
    for _name, tree in trees:
        for defdat in _data_body(tree):
            for item in defdat.children[-1].children:
                if not isinstance(item, Tree):
                    continue
                if item.data in ("enum_decl", "struc_decl"):
                    types.add(str(item.children[1]).upper())
                elif item.data == "decl":
                    data.update(_decl_names(item))
                elif item.data == "signal_decl":
                    data.add(str(item.children[0]).upper())
                elif item.data == "global_signal_decl":
                    data.add(str(item.children[1]).upper())
    return types, data


def _builtin_beside(trees: list):
    """The built-in $config.dat beside the given ones: what they declare is theirs (their ENUM, STRUC, DECL,
    SIGNAL), the built-in fills only what they lack, and its data of a type they redeclare keeps its name
    without its value (a value written for the built-in type is not checked against theirs)."""
    types, data = _declared(trees)
    tree = copy.deepcopy(_builtin_config())
    for defdat in _data_body(tree):
        body = defdat.children[-1]
        kept = []
        for item in body.children:
            if isinstance(item, Tree) and item.data in ("enum_decl", "struc_decl"):
                if str(item.children[1]).upper() in types:
                    continue
            elif isinstance(item, Tree) and item.data == "decl":
                items = [c for c in item.children if isinstance(c, Tree) and c.data == "decl_item"]
                type_name = next(str(t).upper() for t in item.children if isinstance(t, Token) and t.type == "NAME")
                for sub in items:
                    if type_name in types:
                        sub.children[2] = None
                mine = [sub for sub in items if str(sub.children[0]).upper() not in data]
                if not mine:
                    continue
                item.children = [c for c in item.children if not (isinstance(c, Tree) and c.data == "decl_item")]
                item.children += mine
            kept.append(item)
        body.children = kept
    return tree


def _data_body(tree):
    for item in tree.children:
        if isinstance(item, Tree) and item.data == "defdat":
            yield item


def _routines(tree):
    for item in tree.children:
        if isinstance(item, Tree) and item.data in ("def_routine", "def_function"):
            yield item


def routine_name(node) -> str:
    return str(node.children[1 if node.data == "def_routine" else 2]).upper()


def _decl_names(decl) -> list[str]:
    items = [item for item in decl.children if isinstance(item, Tree) and item.data == "decl_item"]
    return [str(item.children[0]).upper() for item in items]


class Linker:
    """Compile a program's modules into one KRLCompiler (findings: codegen check collects errors there)."""

    def __init__(self, files: list[SourceFile], findings: list | None = None, strict: bool = True) -> None:
        self.files = files
        self.findings = findings
        main = files[0]
        if main.suffix == ".dat":
            raise RunError(f"{main.name}: a data list is read together with its program: give the program file first")
        self.compiler = KRLCompiler(main.name)
        self.compiler.findings = findings
        self.compiler.strict_names = strict
        read = ", ".join(Path(f.name).name for f in files if f.suffix != eki.SUFFIX)
        self.compiler.undefined_note = (
            f", declared in none of the files read ({read}): a misspelt name, or the data list that declares it GLOBAL"
            " (DEFDAT ... PUBLIC) is not in the program's folder"
        )
        self.compiler._shapes = ShapeCache(f"<{main.name}: compiled>")  # named by the program, not its first file

    def fail_or_keep(self, exc: RunError) -> None:
        if self.findings is None:
            raise exc
        self.findings.append(exc)

    def parse_all(self) -> tuple[list[Module], list[Module]]:
        modules, configs = group_modules(self.files, first_is_program=True)
        given = []
        for f in configs:
            try:
                given.append(Module("$CONFIG", dat=f, trees=[(f.name, parse(f.text, f.name))], config=True))
            except RunError as exc:
                self.fail_or_keep(exc)
        builtin = _builtin_beside([t for m in given for t in m.trees]) if given else _builtin_config()
        config_modules = [Module("$CONFIG", trees=[(CONFIG_NAME, builtin)], config=True), *given]
        for module in modules:
            for f in (module.dat, module.src):
                if f is None:
                    continue
                try:
                    module.trees.append((f.name, parse(f.text, f.name)))
                except RunError as exc:
                    self.fail_or_keep(exc)
        return config_modules, modules

    def link(self) -> Program:
        compiler = self.compiler
        config_modules, modules = self.parse_all()
        main = modules[0]
        everything = [*config_modules, *modules]
        for module in everything:  # pass 1: the types (every module's, before any declaration uses one)
            for name, tree in module.trees:
                compiler.filename = name
                for sub in tree.iter_subtrees_topdown():
                    if sub.data in ("enum_decl", "struc_decl"):
                        self.guarded(compiler.declare_types, sub)
        compiler.filename = main.src.name if main.src else main.name
        self.guarded(compiler.check_types)
        global_data, own_data, global_routines, own_routines, external, signatures = self.names(everything, main)
        compiler.user_routines = {key for table in [global_routines, *own_routines.values()] for key in table.values()}
        compiler.signatures = {key: modes for key, (_kind, modes) in signatures.items()}
        compiler.routine_signatures = signatures
        config_signals: dict = {}  # $config.dat's signals: every module's (a module's own: its scope's copy)
        shared_signals: dict = {}  # the GLOBAL SIGNAL declarations of data lists: every module's

        def scope_of(module: Module) -> Scope:
            if id(module) not in scopes:
                scopes[id(module)] = Scope(
                    module.name,
                    {**global_data, **own_data.get(id(module), {})},
                    {**global_routines, **own_routines.get(id(module), {})},
                    config_signals if module.config else ChainMap({}, shared_signals, config_signals),
                    external.get(id(module), set()),
                    config_signals if module.config else shared_signals,
                )
            return scopes[id(module)]

        scopes: dict[int, Scope] = {}
        main_key = None
        for module in [*config_modules, *[m for m in modules if m is not main], main]:  # pass 2: data lists
            compiler.scope = scope_of(module)
            for name, tree in module.trees:
                compiler.filename = name
                for defdat in _data_body(tree):
                    self.guarded(compiler.data_list, defdat, own_data[id(module)])
        for module in modules:  # pass 3: routines
            compiler.scope = scope_of(module)
            for name, tree in module.trees:
                compiler.filename = name
                for i, node in enumerate(_routines(tree)):
                    key = compiler.scope.routines[routine_name(node)]
                    if module is main and i == 0:
                        main_key = key
                    self.guarded(compiler.routine, node, key)
        compiler.filename = main.src.name if main.src else main.name
        if main_key is None:
            self.fail_or_keep(RunError(f"{compiler.filename}: no routine (DEF) to run"))
        program = Program(compiler.filename, compiler, compiler.init_data, main_key)
        # the Ethernet KRL channels' configurations among the files, by channel name (EKI_Init's argument)
        program.eki_configs = {f.stem.upper(): f.text for f in self.files if f.suffix == eki.SUFFIX}
        try:
            program.unknown_inputs(())  # the data lists' values, now: a wrong one is reported as the file's
        except RunError as exc:
            self.fail_or_keep(exc)
        return program

    def guarded(self, fn, *args) -> None:
        try:
            fn(*args)
        except RunError as exc:
            self.fail_or_keep(exc)

    def names(self, everything: list[Module], main: Module):
        """Every module's data and routines by name -> storage key: (global data, own data by module, global
        routines, own routines by module, EXT names by module, routine signatures by key)."""
        global_data: dict[str, str] = {}
        own_data: dict[int, dict] = {}
        global_routines: dict[str, str] = {}
        own_routines: dict[int, dict] = {}
        external: dict[int, set] = {}
        signatures: dict[str, tuple] = {}
        where: dict[str, str] = {}
        for module in everything:
            mine, routines, ext = own_data.setdefault(id(module), {}), own_routines.setdefault(id(module), {}), set()
            external[id(module)] = ext
            for name, tree in module.trees:
                for sub in tree.iter_subtrees_topdown():
                    if sub.data in ("ext_routine", "ext_function"):
                        ext.add(str(sub.children[1 if sub.data == "ext_routine" else 2]).upper())
                for defdat in _data_body(tree):
                    public = defdat.children[1] is not None
                    for item in defdat.children[-1].children:
                        if not isinstance(item, Tree) or item.data not in ("decl", "signal_decl"):
                            continue
                        names = _decl_names(item) if item.data == "decl" else []
                        is_global = module.config or (
                            public and any(isinstance(t, Token) and t.type == "GLOBAL" for t in item.children)
                        )
                        for key in names:
                            if key in SYSTEM_ARRAYS:  # the controller's numbered data: the interpreter's own
                                continue
                            if module.config or is_global:
                                previous = where.get(key)
                                if previous is not None and not module.config and previous != name:
                                    twice = f"{name}: {key} is declared GLOBAL twice (also in {previous})"
                                    self.fail_or_keep(RunError(twice))
                                where[key] = name
                                global_data[key] = key
                            store = key if module is main or module.config or is_global else f"{module.name}:{key}"
                            mine[key] = store
                for i, node in enumerate(_routines(tree)):
                    key = routine_name(node)
                    is_global = node.children[0] is not None or (i == 0 and name.lower().endswith(KRL.suffixes))
                    store = key if module is main or is_global else f"{module.name}:{key}"
                    if is_global:
                        if key in global_routines:
                            also = where["routine " + key]
                            self.fail_or_keep(RunError(f"{name}: routine {key} is defined twice (also in {also})"))
                        where["routine " + key] = name
                        global_routines[key] = store
                    if key in routines:
                        self.fail_or_keep(RunError(f"{name}: routine {key} defined twice"))
                    routines[key] = store
                    signatures[store] = _signature(node)
        return global_data, own_data, global_routines, own_routines, external, signatures


def _signature(node) -> tuple[str, list[str]]:
    function = node.data == "def_function"
    params = node.children[3] if function else node.children[2]
    modes = []
    for param in params.children if params is not None else []:
        mode = param.children[2]
        modes.append(str(mode).upper() if mode is not None else "IN")
    return ("DEFFCT" if function else "DEF", modes)


def load_files(files: list[SourceFile]) -> Program:
    """One program from its files (the program file first, as programs() groups them)."""
    return Linker(files).link()


def load(text: str, filename: str, dat_text: str | None = None) -> Program:
    """A .src (with its .dat beside it when given) compiled into a runnable program, as Dialect.load has always
    done: a name or routine defined nowhere fails when the statement runs (load_files and check refuse it)."""
    files = [SourceFile(filename, text)]
    if dat_text is not None:
        files.append(SourceFile(str(Path(filename).with_suffix(".dat")), dat_text))
    return Linker(files, strict=False).link()
