"""Registry of controller languages: each folder defines one Dialect subclass, registered on definition."""

from __future__ import annotations

import importlib
import pkgutil
import re
from functools import cache
from pathlib import Path
from typing import ClassVar

_TERMINAL = re.compile(r"^([A-Z_]+): /(.*)/$", re.MULTILINE)
_IMPORT = re.compile(r"^%import terminals \(([\w, ]+)\)$", re.MULTILINE)  # core/terminals.lark's, by name
SHARED_TERMINALS = Path(__file__).parent / "core" / "terminals.lark"
_RESERVED = re.compile(r"^NAME(?:\.\d+)?: /\(\?!(\(\?i:)?\(([\w|]+)\)", re.MULTILINE)


class Dialect:
    """A controller language: its printer, grammar, interpreter and file suffixes.

    Subclasses live in `codegen/dialects/<name>/__init__.py` and only name modules of their own
    folder; nothing outside that folder names a dialect. Importing a dialect is cheap: the
    printer (sympy) and the interpreter (lark) are imported when first used.
    """

    name: ClassVar[str] = ""
    suffixes: ClassVar[tuple[str, ...]] = ()  # program files, e.g. (".src",)
    companions: ClassVar[tuple[str, ...]] = ()  # data files read together with a program, e.g. a data list
    # files a program reads when it runs, in a format of their own (a channel's configuration): beside it, checked
    # by the dialect's check, given to the program with its files
    configurations: ClassVar[tuple[str, ...]] = ()
    encodings: ClassVar[tuple[str, ...]] = ()  # the controller's text encodings besides UTF-8 (its backups')
    # how the controller starts a program at a routine of its own choosing (e.g. RAPID's "PP to Routine"), None:
    # only at the program's entry; load_files(files, entry=NAME) then starts there
    entry_routines: ClassVar[str | None] = None
    registry: ClassVar[dict[str, type[Dialect]]] = {}

    def __init_subclass__(cls, **kwargs) -> None:
        super().__init_subclass__(**kwargs)
        Dialect.registry[cls.name] = cls

    @classmethod
    def module(cls, name: str):
        """A module of this dialect's folder (printer, interpreter)."""
        return importlib.import_module(f"{cls.__module__}.{name}")

    @classmethod
    def keywords(cls) -> frozenset[str]:
        """The words the language reserves, as its grammar's NAME terminal excludes them (upper case
        where the language ignores case); a generated identifier must not be one."""
        return _keywords(cls._grammar())

    @classmethod
    def terminal(cls, name: str) -> str | None:
        """The regular expression of one of the grammar's terminals (e.g. STRING, COMMENT), or None."""
        return _terminals(cls._grammar()).get(name)

    @classmethod
    def predefined(cls) -> frozenset[str]:
        """The names the controller's standard environment defines (built-in routines, predefined data, data
        types; upper case where the language ignores case): a generated name must not be one."""
        return frozenset()

    @classmethod
    def _grammar(cls) -> Path:
        return Path(importlib.import_module(cls.__module__).__file__).parent / "grammar.lark"

    @classmethod
    def printer(cls):
        """A configured sympy code printer (imports sympy)."""
        return cls.module("printer").Printer()

    @classmethod
    def parse(cls, text: str, filename: str, positions: bool = True):
        """Parse tree of a program or companion file; raises with file:line:column on an error."""
        return cls.module("interpreter").parse(text, filename, positions)

    @classmethod
    def check(cls, text: str, filename: str) -> None:
        """Raise as parse would, faster and without a tree (generate's check of what it writes)."""
        from codegen.dialects.core.parsing import check_with_grammar

        check_with_grammar(cls.module("interpreter").__file__, text, filename)

    @classmethod
    def move_settings(
        cls, program: dict, kind: str, exact: bool, own_tool=False, speed_mm_s=None, zone_mm=0.0, joint_percent=None
    ) -> dict:
        """How a correct program moves the arm to a pose, as the interpreter records it (MoveEvent
        settings): from the target's [program] facts and the cell's [cell.motion] (speed_mm_s: the
        segment's TCP speed, None where the facts decide; zone_mm: its blending zone, 0: a stop);
        `exact` where the arm must stop at the pose (a work pose, a photo pose), so no blending;
        `own_tool` where the program declares the cell's tool. Empty: the language states nothing to
        compare."""
        return {}

    @classmethod
    def zone_mm(cls, settings: dict) -> float:
        """A recorded move's blending zone (MoveEvent.settings): the radius (mm) about its target within which the
        arm leaves its path for the next move's; 0: it stops there, or the language records no radius."""
        return 0.0

    @classmethod
    def circular(cls, kind: str, settings: dict) -> bool:
        """Whether a recorded move (its MoveEvent kind and settings) is a circular one (its path an arc)."""
        return False

    @classmethod
    def load(cls, text: str, filename: str, companions: dict[str, str] | None = None):
        """A compiled program; `companions` maps a companion suffix to its text."""
        return cls.module("interpreter").load(text, filename)

    @classmethod
    def programs(cls, files: list) -> list[list]:
        """Which of the given files (codegen.dialects.core.files.SourceFile, all of this language) make one
        program each, the program file first: by default each program file with its companions of the same
        name (a program and its data list); a language whose program spans several files (the modules of one
        task, modules calling each other's global routines) groups them by its scope rules. A companion
        without its program file is an error (RunError naming it)."""
        from codegen.dialects.core.values import RunError

        groups = [[f] for f in files if f.suffix in cls.suffixes]
        for f in files:
            if f.suffix in cls.suffixes:
                continue
            owner = next((g for g in groups if g[0].stem == f.stem), None)
            if owner is None:
                raise RunError(f"{f.name}: a data file is read together with its program: give the program too")
            owner.append(f)
        return groups

    @classmethod
    def beside(cls, path) -> list:
        """The data files a program file given alone brings from its folder (Paths, not the program itself): by
        default its companions of its own name (a .src's .dat), in the case found on disk."""
        out = []
        for suffix in cls.companions:
            for candidate in (path.with_suffix(suffix), path.with_suffix(suffix.upper())):
                if candidate.is_file():
                    out.append(candidate)
                    break
        return out

    @classmethod
    def shared_among(cls, program, files: list) -> list:
        """The files of the other programs of one folder that a program file (SourceFile) is read with, as
        Dialect.beside takes them from a folder on disk: by default none."""
        return []

    @classmethod
    def load_files(cls, files: list):
        """One program from its files (SourceFile, the program file first, as programs() groups them)."""
        main, rest = files[0], files[1:]
        return cls.load(main.text, main.name, {f.suffix: f.text for f in rest})

    @classmethod
    def check_files(cls, files: list, options=None) -> list:
        """Every finding of `codegen check` in one program's files (codegen.dialects.core.files.Finding),
        without running it. What every language shares, a dialect's override adding its own checks (calling
        this first): each file's syntax errors (every file parsed, so a syntax error in one does not hide
        another's), then, where all parse, what loading the program refuses (an unsupported statement, an
        undefined routine: severity "unsupported" where the message says what is not modelled). options:
        codegen.dialects.core.files.CheckOptions (the arm, from --robot), or None."""
        from codegen.dialects.core.files import finding_of
        from codegen.dialects.core.values import RunError

        findings = []
        for f in files:
            try:
                cls.parse(f.text, f.name, positions=False)
            except RunError as exc:
                findings.append(finding_of(exc, [f], "syntax"))
            except RecursionError:
                findings.append(finding_of(f"{f.name}: statements or expressions nested too deeply", [f], "syntax"))
        if findings:
            return findings
        try:
            cls.load_files(files)
        except RunError as exc:
            findings.append(finding_of(exc, files))
        except RecursionError:
            findings.append(finding_of(f"{files[0].name}: statements or expressions nested too deeply", files))
        return findings


@cache
def _keywords(grammar: Path) -> frozenset[str]:
    match = _RESERVED.search(grammar.read_text(encoding="utf-8")) if grammar.is_file() else None
    if match is None:
        return frozenset()
    caseless, words = match.group(1), match.group(2).split("|")
    return frozenset(w.upper() for w in words) if caseless else frozenset(words)


@cache
def _terminals(grammar: Path) -> dict[str, str]:
    text = grammar.read_text(encoding="utf-8") if grammar.is_file() else ""
    own = {m.group(1): m.group(2) for m in _TERMINAL.finditer(text)}
    imported = {name.strip() for m in _IMPORT.finditer(text) for name in m.group(1).split(",")}
    shared = _terminals(SHARED_TERMINALS) if imported else {}
    return {**{name: shared[name] for name in sorted(imported)}, **own}


@cache
def dialects() -> dict[str, type[Dialect]]:
    """Every dialect folder under codegen/dialects, imported once: name -> Dialect subclass."""
    for info in pkgutil.iter_modules(__path__):
        if info.ispkg:
            importlib.import_module(f"{__name__}.{info.name}")
    return dict(Dialect.registry)


def get_dialect(name: str) -> type[Dialect]:
    known = dialects()
    if name not in known:
        raise KeyError(f"unknown dialect {name!r}; known: {', '.join(sorted(known))}")
    return known[name]


def printers() -> dict:
    """One configured sympy code printer per dialect (imports sympy)."""
    return {name: dialect.printer() for name, dialect in dialects().items()}


def dialect_of_suffix(suffix: str) -> type[Dialect] | None:
    """The dialect whose program or companion files end in `suffix` (a program or a data file)."""
    for dialect in dialects().values():
        if suffix.lower() in dialect.suffixes + dialect.companions + dialect.configurations:
            return dialect
    return None


def is_companion(path) -> bool:
    """A data file read together with its program (e.g. a data list beside its program), not a program."""
    suffix = str(path).rsplit(".", 1)[-1].lower()
    return any("." + suffix in dialect.companions for dialect in dialects().values())


def _dialect_of_file(name: str) -> type[Dialect]:
    suffix = "." + name.rsplit(".", 1)[-1].lower()
    dialect = dialect_of_suffix(suffix)
    if dialect is None:
        raise ValueError(f"{name}: unknown program suffix {suffix}")
    return dialect


def parse_program(name: str, text: str, positions: bool = True):
    """Parse a program or companion file with the grammar its suffix names."""
    return _dialect_of_file(name).parse(text, name, positions)


def check_program(name: str, text: str) -> None:
    """Check a program or companion file against the grammar its suffix names; raises as parse_program."""
    _dialect_of_file(name).check(text, name)
