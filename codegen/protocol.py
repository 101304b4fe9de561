"""The program-kind protocol and its registry: each package under codegen/kinds/ defines one ProgramKind."""

from __future__ import annotations

import importlib
import importlib.util
import pkgutil
from dataclasses import dataclass, field
from functools import cache
from typing import Any, ClassVar

from codegen.controllers import get_target, target_names


@dataclass(frozen=True)
class ProgramFile:
    """One file of a program: its name under <cell>/<target>/ and the template it is rendered from."""

    name: str
    template: str  # under templates/, e.g. "<target>/kinds/<kind>.src.j2"
    context: dict = field(default_factory=dict, compare=False)  # variables of this file alone (beside the plan's)


@dataclass(frozen=True)
class ProgramPlan:
    """One program a kind writes for a target: its name (a report row), its files (the program file first) and
    the template variables the kind adds to the shared ones (codegen.render.shared_context)."""

    kind: str
    ident: str
    files: tuple[ProgramFile, ...]
    context: dict = field(default_factory=dict, compare=False)
    index: int = 0  # which of the kind's programs, where it writes several (one per table of its section)
    # the routine a run starts at where the program has none of the language's own entry (a RAPID module loaded into
    # the production task, whose main calls it): verify runs it as after "PP to Routine"; None: the language's entry
    entry: str | None = None


class ProgramKind:
    """What a program kind owns (its package codegen/kinds/<name>/, its templates templates/<t>/kinds/<name>*.j2,
    its table [program.<name>] in targets/<t>.toml): its cell-file tables and their validation, its programs per
    target and their template context, its reach proof, its identities, its verify section and its commands.
    Nothing outside a kind's package names it: cell, render, generate, verify and cli loop over the registry."""

    name: ClassVar[str] = ""  # "" for an abstract base: not registered
    order: ClassVar[int] = 100  # where the kind comes in reports and programs, lowest first
    # the kind's part of the cell file's definition (codegen.model.schema.KindKeys): its tables and keys, their
    # types, ranges and defaults; tables and cell_tables follow from it
    cell_file: ClassVar[Any] = None
    tables: ClassVar[frozenset[str]] = frozenset()  # top-level tables of a cell file the kind owns
    cell_tables: ClassVar[frozenset[str]] = frozenset()  # [cell.<name>] tables of this kind
    target_keys: ClassVar[dict[str, type]] = {}  # its [program.<name>] table: key -> type
    # its program is named after the cell: a program file given to verify under a name of its own (a hand-edited
    # copy) is taken for it
    renamed_copies: ClassVar[bool] = False
    registry: ClassVar[dict[str, type[ProgramKind]]] = {}

    def __init_subclass__(cls, **kwargs) -> None:
        super().__init_subclass__(**kwargs)
        if "cell_file" in cls.__dict__ and cls.cell_file is not None:
            cls.tables = frozenset(cls.cell_file.tables)
            cls.cell_tables = frozenset(cls.cell_file.cell_tables)
        if cls.name:
            ProgramKind.registry[cls.name] = cls

    # --- cell file -------------------------------------------------------------------------
    @classmethod
    def parse_section(cls, ctx, data: dict, cell) -> Any:
        """The kind's part of the cell model from its top-level tables (None: the cell has none); cell is
        the cell as far as it is known (targets, pose format, robot, io, motion), ctx the validator."""
        return None

    @classmethod
    def listed_names(cls) -> tuple[str, ...]:
        """The names the cell file's reference lists the kind's tables under (a kind with modes: its modes')."""
        return (cls.name,)

    @classmethod
    def json_schema(cls, schema: dict) -> None:
        """Add the rules between the kind's tables to the cell file's JSON Schema (codegen.model.tables)."""

    @classmethod
    def standalone(cls, data: dict) -> bool:
        """Whether the kind's tables in a cell file make a cell without [[station]] (no camera, no limits)."""
        return False

    @classmethod
    def parse_settings(cls, ctx, cell_table: dict):
        """The kind's settings from its [cell.<name>] tables (kept in Cell.settings[kind name])."""
        return None

    @classmethod
    def check_cell(cls, ctx, cell) -> None:
        """Checks that need the whole cell (the signals the kind's programs use, the arm)."""

    @classmethod
    def section(cls, cell) -> Any:
        """The kind's part of a cell (parse_section's result), or None."""
        return cell.sections.get(cls.name)

    # --- controllers -----------------------------------------------------------------------
    @classmethod
    def facts(cls, target) -> dict:
        """The kind's [program.<name>] table of a target, checked against target_keys ({}: none)."""
        return _facts(cls, target.name)

    # --- programs --------------------------------------------------------------------------
    @classmethod
    def programs(cls, cell, target) -> list[ProgramPlan]:
        """The kind's programs for one target, with their template context (EmitError: cannot be written)."""
        return []

    @classmethod
    def reach(cls, cell, targets: list[str]) -> list:
        """The kind's reach proof for the targets with an arm (codegen.robot.expect.Margins each; ReachError)."""
        return []

    @classmethod
    def identities(cls, check) -> list:
        """The kind's identities for `codegen derive --check` (codegen.derivation._check makes each one)."""
        return []

    @classmethod
    def derive(cls) -> Any:
        """The kind's derivation that its description and identities read (sympy; None: the kind has none)."""
        return None

    @classmethod
    def describe_derivation(cls, derivation) -> str:
        """The kind's derivation for `codegen derive` ("": nothing to say)."""
        return ""

    @classmethod
    def derivation_symbols(cls) -> dict:
        """The kind's conventions for the shared proof and printing (codegen.derivation): "free" symbols every
        counterexample search draws, "small" angles drawn near 0, "readable" {expression: name} of the printed
        blocks' common subexpressions."""
        return {}

    @classmethod
    def printed_blocks(cls) -> dict:
        """The kind's closed forms the controllers evaluate: block -> {output name: sympy expression}, printed
        per dialect into derived.json (codegen.derived.printed(dialect, block)); imports sympy when asked."""
        return {}

    # --- verify (codegen/verify/: the engine runs every kind through these) ---------------------
    # Each scenario every kind runs (codegen.verify.plan.SCENARIOS) -> "" where the kind runs it, else the
    # reason it cannot apply to the kind's programs (a test holds every kind to this table).
    scenarios: ClassVar[dict[str, str]] = {}
    report_key: ClassVar[str] = ""  # the kind's rows also under this key of verify's JSON ("" : name + "s")

    @classmethod
    def verify_models(cls, cell) -> list[tuple[Any, bool]]:
        """The cells the kind's fresh programs are made from and judged against (default: the cell itself)."""
        return [(cell, True)]

    @classmethod
    def verify_cases(cls, cell, source, count: int, seed: int) -> list:
        """The cases of one of the kind's programs (source: codegen.verify.programs.ProgramSource): its own
        and the common scenarios' (codegen.verify.plan.Case or the kind's picklable equivalent)."""
        return []

    @classmethod
    def sweeps(cls, cell, source, workers: int) -> list[range]:
        """Bulk runs of the program in ranges (e.g. every station id that is no station), or none."""
        return []

    @classmethod
    def sweep(cls, cell, source, program, ids: range, step_limit: int, row) -> None:
        """Run the bulk range `ids` on the program, counting into the report row."""

    @classmethod
    def setup(cls, cell, source, case):
        """How the case runs (codegen.verify.plan.Setup): inputs, simulated devices, start joints, ..."""
        raise NotImplementedError

    @classmethod
    def judge(cls, cell, source, case, trace, setup):
        """The run's codegen.verify.plan.Judgement: what a correct program does here (from the kind's float64
        reference; a device's log where the reference depends on the run, such as a belt's parts)."""
        raise NotImplementedError

    @classmethod
    def scenario_of(cls, case) -> str:
        return getattr(case, "scenario", "nominal")

    @classmethod
    def log_prefixes_of(cls, cell) -> tuple[str, ...]:
        """The program's log lines whose numbers the expectations' `logged` name."""
        return ()

    @classmethod
    def describe(cls, cell, case) -> str:
        """The case's situation in a mismatch line, after its category."""
        return ""

    @classmethod
    def new_figures(cls):
        """The kind's own report figures of a program (None: it has none)."""
        return None

    @classmethod
    def add_figures(cls, figures, case, judged) -> None:
        """Count a passing case's figures (Judgement.figures) in the program's."""

    @classmethod
    def merge_figures(cls, into, part) -> None:
        """Add the figures of another chunk of cases."""

    @classmethod
    def summary(cls, row) -> dict:
        """The kind's own keys in a row's JSON."""
        return {}

    @classmethod
    def legacy_summary(cls, row) -> dict:
        """A row as the kind's own JSON list (report_key) has it."""
        return row.summary()

    @classmethod
    def report_lines(cls, rows: list) -> list[str]:
        """The kind's own figures as text lines of the report (rows: its programs')."""
        return []

    # --- the cell's page (codegen/view/) ------------------------------------------------------
    @classmethod
    def scene(cls, cell) -> list[dict]:
        """The kind's objects of the cell as the page draws them (codegen.view.scene's vocabulary): its stations'
        or its section's (none: [])."""
        return []

    # --- command line ----------------------------------------------------------------------
    @classmethod
    def commands(cls) -> list[tuple[str | None, Any]]:
        """The kind's click commands: (the group they belong to, e.g. "calibrate", or None, command)."""
        return []


class TargetFactsError(Exception):
    """A [program.<kind>] table of a targets/<t>.toml that names an unknown key or has the wrong type."""


@cache
def _facts(kind: type[ProgramKind], target_name: str) -> dict:
    target = get_target(target_name)
    table = target.kind_tables.get(kind.name, {})
    where = f"targets/{target_name}.toml: program.{kind.name}"
    for key, value in table.items():
        want = kind.target_keys.get(key)
        if want is None:
            raise TargetFactsError(f"{where}.{key}: unknown key; known: {', '.join(kind.target_keys)}")
        if isinstance(value, bool) is not (want is bool) or not isinstance(value, want):
            raise TargetFactsError(f"{where}.{key}: expected {want.__name__}")
    return dict(table)


@cache
def kinds() -> dict[str, type[ProgramKind]]:
    """Every kind package under codegen/kinds (found, not named: each registers itself when its `kind`
    module is imported), in the order of `order` then by name."""
    package = importlib.import_module("codegen.kinds")
    for info in pkgutil.iter_modules(package.__path__):
        if info.ispkg and importlib.util.find_spec(f"codegen.kinds.{info.name}.kind") is not None:
            importlib.import_module(f"codegen.kinds.{info.name}.kind")
    registered = ProgramKind.registry
    out = {name: registered[name] for name in sorted(registered, key=lambda n: (registered[n].order, n))}

    for target in target_names():  # a kind table no kind reads, or a fact of the wrong type, is refused here
        unknown = sorted(set(_target_tables(target)) - set(out))
        if unknown:
            raise TargetFactsError(f"targets/{target}.toml: program.{unknown[0]}: no program kind of this name")
        for kind in out.values():
            _facts(kind, target)
    return out


def _target_tables(target_name: str) -> dict:
    return get_target(target_name).kind_tables


def get_kind(name: str) -> type[ProgramKind]:
    known = kinds()
    if name not in known:
        raise KeyError(f"unknown program kind {name!r}; known: {', '.join(known)}")
    return known[name]
