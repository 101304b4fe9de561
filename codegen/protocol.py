"""A program kind as an object made of parts with one job each, and the registry of the installed kinds."""

from __future__ import annotations

import importlib
import operator
from collections.abc import Hashable, Iterator, Mapping
from dataclasses import dataclass, field, fields
from functools import cache
from importlib.metadata import entry_points
from pathlib import Path
from typing import Any, ClassVar

from codegen.controllers import get_target, target_names

GROUP = "codegen.kinds"  # the entry-point group a distribution registers its kinds in (name = "module:Kind object")


@dataclass(frozen=True)
class ProgramFile:
    """One file of a program: its name under <cell>/<target>/ and the template it is rendered from."""

    name: str
    template: str  # under templates/ (or the kind's own templates folder), e.g. "<target>/kinds/<kind>.src.j2"
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


class Part:
    """One job of a kind, made once per kind with the kind at hand (its name, its facts, its other parts)."""

    def __init__(self, kind: Kind) -> None:
        self.kind = kind


class Section(Part):
    """The kind's part of the cell file: its tables and keys (codegen.model.schema.KindKeys), their parse into the
    cell model, its [cell.<name>] settings, the checks that need the whole cell, its JSON Schema rules."""

    keys: ClassVar[Any] = None  # the kind's KindKeys: its tables, their types, ranges and defaults

    @property
    def tables(self) -> frozenset[str]:
        """The top-level tables of a cell file the kind owns."""
        return frozenset(() if self.keys is None else self.keys.tables)

    @property
    def cell_tables(self) -> frozenset[str]:
        """The [cell.<name>] tables of the kind."""
        return frozenset(() if self.keys is None else self.keys.cell_tables)

    def parse(self, ctx, data: dict, cell) -> Any:
        """The kind's part of the cell model from its top-level tables (None: the cell has none); cell is the cell as
        far as it is known (targets, pose format, robot, io, motion, the kinds it is loaded with), ctx the validator."""
        return None

    def standalone(self, data: dict) -> bool:
        """Whether the kind's tables in a cell file make a cell without [[station]] (no camera, no limits)."""
        return False

    def settings(self, ctx, cell_table: dict) -> Any:
        """The kind's settings from its [cell.<name>] tables (kept in Cell.settings[kind name])."""
        return None

    def check(self, ctx, cell) -> None:
        """Checks that need the whole cell (the signals the kind's programs use, the arm)."""

    def json_schema(self, schema: dict) -> None:
        """Add the rules between the kind's tables to the cell file's JSON Schema (codegen.model.tables)."""

    def listed_names(self) -> tuple[str, ...]:
        """The names the cell file's reference lists the kind's tables under (a kind with modes: its modes')."""
        return (self.kind.name,)

    def starters(self) -> dict[str, Any]:
        """The starters `codegen init NAME` writes of the kind, by NAME: a function from the text of the kind's bundled
        example to the starter's text, or None for the example as it is (a kind with modes: one per mode)."""
        return {self.kind.name: None}

    def of(self, cell) -> Any:
        """The kind's part of a cell (parse's result), or None."""
        return cell.sections.get(self.kind.name)


class Writer(Part):
    """The kind's programs per target (with their template context) and its reach proof."""

    # its program is named after the cell: a program file given to verify under a name of its own (a hand-edited
    # copy) is taken for it
    renamed_copies: ClassVar[bool] = False

    def programs(self, cell, target) -> list[ProgramPlan]:
        """The kind's programs for one target, with their template context (EmitError: cannot be written)."""
        return []

    def reach(self, cell, targets: list[str]) -> list:
        """The kind's reach proof for the targets with an arm (codegen.robot.expect.Margins each; ReachError)."""
        return []


class Derivation(Part):
    """The kind's symbolic side (sympy, imported only when asked): `codegen derive`'s identities and text, the
    conventions of the shared proof and the closed forms printed into derived.json."""

    def derive(self) -> Any:
        """The kind's derivation that its description and identities read (None: the kind has none)."""
        return None

    def describe(self, derivation) -> str:
        """The kind's derivation for `codegen derive` ("": nothing to say)."""
        return ""

    def identities(self, check) -> list:
        """The kind's identities for `codegen derive --check` (codegen.derivation._check makes each one)."""
        return []

    def symbols(self) -> dict:
        """The kind's conventions for the shared proof and printing (codegen.derivation): "free" symbols every
        counterexample search draws, "small" angles drawn near 0, "readable" {expression: name} of the printed
        blocks' common subexpressions."""
        return {}

    def printed_blocks(self) -> dict:
        """The kind's closed forms the controllers evaluate: block -> {output name: sympy expression}, printed
        per dialect into derived.json (codegen.derived.printed(dialect, block))."""
        return {}


@dataclass
class Figures:
    """A program's own report figures, as a dataclass whose fields add up: `a + b` is two chunks of cases together
    (each field by its metadata's "add", default `+`), `count` adds one passing case, `as_json` gives the row's keys."""

    def __add__(self, other: Figures) -> Figures:
        return type(self)(
            **{
                f.name: f.metadata.get("add", operator.add)(getattr(self, f.name), getattr(other, f.name))
                for f in fields(self)
            }
        )

    def count(self, case, judged) -> None:
        """Add a passing case's figures (its Judgement.figures) in place."""
        raise NotImplementedError

    def as_json(self) -> dict:
        """The figures' keys in the program's row of verify's JSON."""
        return {}


def most(a, b):
    """A figure that is the largest of its chunks' (Figures field metadata "add")."""
    return max(a, b)


class VerifyPlan(Part):
    """How verify runs the kind's programs (codegen/verify/ runs every kind through its plan): the models, the cases
    and bulk sweeps, each case's setup and judgement, its words in a mismatch, the figures and report lines."""

    # Each scenario every kind runs (codegen.verify.plan.SCENARIOS) -> "" where the kind runs it, else the
    # reason it cannot apply to the kind's programs (a test holds every kind to this table).
    scenarios: ClassVar[dict[str, str]] = {}
    report_key: ClassVar[str] = ""  # the kind's rows also under this key of verify's JSON ("": name + "s")
    figures: ClassVar[type[Figures] | None] = None  # the kind's own figures of a program (None: it has none)
    # a row as the kind's own JSON list (report_key) has it: its key -> a key of the row's JSON ("a.b": b of a;
    # "*": every key of the row)
    listed: ClassVar[dict[str, str]] = {"*": "*"}

    def models(self, cell) -> list[tuple[Any, bool]]:
        """The cells the kind's fresh programs are made from and judged against (default: the cell itself)."""
        return [(cell, True)]

    def cases(self, cell, source, count: int, seed: int) -> list:
        """The cases of one of the kind's programs (source: codegen.verify.programs.ProgramSource): its own
        and the common scenarios' (codegen.verify.plan.Case or the kind's picklable equivalent)."""
        return []

    def sweeps(self, cell, source, workers: int) -> list[range]:
        """Bulk runs of the program in ranges (e.g. every station id that is no station), or none."""
        return []

    def sweep(self, cell, source, program, ids: range, step_limit: int, row, every: bool = False) -> None:
        """Run the bulk range `ids` on the program, counting into the report row (every: each id of `ids` run, else
        as many as show every behaviour, codegen.verify.bulk)."""

    def setup(self, cell, source, case):
        """How the case runs (codegen.verify.plan.Setup): inputs, simulated devices, start joints, ..."""
        raise NotImplementedError

    def judge(self, cell, source, case, trace, setup):
        """The run's codegen.verify.plan.Judgement: what a correct program does here (from the kind's float64
        reference; a device's log where the reference depends on the run, such as a belt's parts)."""
        raise NotImplementedError

    def scenario_of(self, case) -> str:
        return getattr(case, "scenario", "nominal")

    def log_prefixes(self, cell) -> tuple[str, ...]:
        """The program's log lines whose numbers the expectations' `logged` name."""
        return ()

    def describe(self, cell, case) -> str:
        """The case's situation in a mismatch line, after its category."""
        return ""

    def figures_json(self, figures: Figures | None) -> dict:
        """The kind's own keys in a row's JSON (its figures', none counted yet where None)."""
        if figures is None:
            return {} if self.figures is None else self.figures().as_json()
        return figures.as_json()

    def listed_row(self, row_json: dict) -> dict:
        """A row as the kind's own JSON list has it (listed), from the row's JSON."""
        out = {}
        for key, path in self.listed.items():
            if path == "*":
                out.update(row_json)
                continue
            value = row_json
            for step in path.split("."):
                value = value[step]
            out[key] = value
        return out

    def report_lines(self, rows: list) -> list[str]:
        """The kind's own figures as text lines of the report (rows: its programs')."""
        return []


@dataclass(frozen=True)
class Stage:
    """What stands and what is carried at a point of a run, beside the cell's fixed solids: key (equal where the
    rest is), the solids that stand only for a while (by name, base frame: codegen.world.solids shapes), the part
    while the gripper holds it (a codegen.model.world.PartShape or a codegen.world.solids.Box in the flange frame;
    None: no shape known), and flush: the (tool or part, solid) pairs a kind's own check holds along the straight
    moves where the gripper acts (a box put down flush with its stack)."""

    key: Hashable
    solids: dict = field(default_factory=dict, compare=False)
    part: Any = None
    flush: frozenset = field(default=frozenset(), compare=False)


class Scene(Part):
    """The kind's objects of the cell: as the page draws them (codegen.view.scene's vocabulary) and as solids the arm
    keeps its clearance from (codegen.world)."""

    def objects(self, cell) -> list[dict]:
        return []

    def solids(self, cell) -> dict[str, Any]:
        """The kind's solids that stand in the cell throughout (codegen.world.solids shapes in the robot's base
        frame, mm), by names unique in the cell: what the kind's programs work at, its housings; {}: none."""
        return {}

    def paths(self, cell, targets: list[str]) -> list:
        """The moves the kind's programs plan on each of the targets' arms, as generate proves them clear of the
        solids (codegen.world.proof.Path each); []: none."""
        return []

    def proven(self, cell, target: str) -> list | None:
        """The least clearances (codegen.world.proof.Least each, in the order of paths) of the kind's paths on the
        target where its plan proved them already (in choosing a posture); None: generate proves paths()."""
        return None

    def carried(self, cell) -> Any:
        """The part the kind's programs carry, as verify sweeps a program's trace without its case (codegen run
        --cell): a codegen.world.solids.Box in the flange frame or a codegen.model.world.PartShape; None: none."""
        return None

    def staged(self, cell, target: str, case) -> Any:
        """What stands and what is carried along a verify case's trace: a function of the grips and releases of the
        gripper so far (counts) giving a Stage (the solids that stand only for a while, such as a station's machine
        moved by the case's reading or the stack as built, and the part in the gripper)."""
        stage = Stage((), {}, self.carried(cell))
        return lambda _grips, _releases: stage


class Commands(Part):
    """The kind's click commands."""

    def commands(self) -> list[tuple[str | None, Any]]:
        """(the group they belong to, e.g. "calibrate", or None, command) each."""
        return []


PARTS: dict[str, type[Part]] = {  # a kind's parts and the base each one's class extends
    "section": Section,
    "writer": Writer,
    "derivation": Derivation,
    "verify": VerifyPlan,
    "scene": Scene,
    "commands": Commands,
}


class TargetFactsError(Exception):
    """A [program.<kind>] table of a targets/<t>.toml that names an unknown key or has the wrong type."""


class Kind:
    """A program kind (its package, its templates templates/<t>/kinds/<name>*.j2, its table [program.<name>] in
    targets/<t>.toml): its name, its place in reports and programs, the keys of its target table, and its parts.
    Each part is given as its class or as "module:Class" and made when first asked, so that loading a cell imports
    the sections alone (not the writers' templates, the verify plans, the scenes, sympy or click)."""

    def __init__(
        self,
        name: str,
        *,
        order: int = 100,
        target_keys: dict[str, type] | None = None,
        templates: Path | None = None,
        planner: str | None = None,
        **parts: str | type[Part],
    ) -> None:
        unknown = set(parts) - set(PARTS)
        if unknown:
            raise TypeError(f"kind {name}: unknown part {sorted(unknown)[0]!r}; parts: {', '.join(PARTS)}")
        self.name = name
        self.order = order  # where the kind comes in reports and programs, lowest first
        self.target_keys = dict(target_keys or {})  # its [program.<name>] table of a target: key -> type
        self.templates = templates  # a folder of its own templates (a kind from outside the tree), searched after
        # "module:function" (cell, target) -> the kind's plan for the cell on the target (None: the kind plans nothing)
        self.planner = planner
        self._refs = parts
        self._made: dict[str, Part] = {}

    def __repr__(self) -> str:
        return f"Kind({self.name!r})"

    def __getstate__(self) -> dict:
        return {**self.__dict__, "_made": {}}  # parts are made again where the kind arrives

    def part(self, which: str) -> Part:
        """The kind's part `which` (a key of PARTS); the base's defaults where the kind gives none."""
        made = self._made.get(which)
        if made is None:
            ref = self._refs.get(which, PARTS[which])
            if isinstance(ref, str):
                module, _, attr = ref.partition(":")
                ref = getattr(importlib.import_module(module), attr)
            made = self._made[which] = ref(self)
        return made

    @property
    def section(self) -> Section:
        return self.part("section")  # type: ignore[return-value]

    @property
    def writer(self) -> Writer:
        return self.part("writer")  # type: ignore[return-value]

    @property
    def derivation(self) -> Derivation:
        return self.part("derivation")  # type: ignore[return-value]

    @property
    def verify(self) -> VerifyPlan:
        return self.part("verify")  # type: ignore[return-value]

    @property
    def scene(self) -> Scene:
        return self.part("scene")  # type: ignore[return-value]

    @property
    def commands(self) -> Commands:
        return self.part("commands")  # type: ignore[return-value]

    def plan(self, cell, target: str) -> Any:
        """The kind's plan for the cell on a target (what its writer, proofs, verify setup and scene read): its
        planner's, worked out once per cell and target and handed down with the cell (Cell.plans); None: no planner."""
        key = (self.name, target)
        plans = cell.plans
        if key not in plans:
            planned = None
            if self.planner is not None:
                module, _, attr = self.planner.partition(":")
                planned = getattr(importlib.import_module(module), attr)(cell, target)
            plans[key] = planned
        return plans[key]

    def facts(self, target) -> dict:
        """The kind's [program.<name>] table of a target, checked against target_keys ({}: none)."""
        return _facts(self, target.name)


@cache
def _facts(kind: Kind, target_name: str) -> dict:
    table = get_target(target_name).kind_tables.get(kind.name, {})
    where = f"targets/{target_name}.toml: program.{kind.name}"
    for key, value in table.items():
        want = kind.target_keys.get(key)
        if want is None:
            raise TargetFactsError(f"{where}.{key}: unknown key; known: {', '.join(kind.target_keys)}")
        if isinstance(value, bool) is not (want is bool) or not isinstance(value, want):
            raise TargetFactsError(f"{where}.{key}: expected {want.__name__}")
    return dict(table)


class Kinds(Mapping):
    """A registry of kinds, by name, in the order of `order` then by name: what a cell is loaded with (and carries
    to generate, verify and the page)."""

    def __init__(self, kinds) -> None:
        listed = list(kinds)
        self._by_name = {k.name: k for k in sorted(listed, key=lambda k: (k.order, k.name))}
        if len(self._by_name) != len(listed):
            raise ValueError(f"two kinds of one name among {', '.join(k.name for k in listed)}")

    def __getitem__(self, name: str) -> Kind:
        try:
            return self._by_name[name]
        except KeyError:
            raise KeyError(f"unknown program kind {name!r}; known: {', '.join(self._by_name)}") from None

    def __iter__(self) -> Iterator[str]:
        return iter(self._by_name)

    def __len__(self) -> int:
        return len(self._by_name)

    __hash__ = object.__hash__  # one registry, one identity: the cell file's definition is cached per registry

    def __eq__(self, other) -> bool:
        return self is other

    def __repr__(self) -> str:
        return f"Kinds({', '.join(self._by_name)})"

    def __reduce__(self):
        if self is installed_kinds():  # a worker process uses its own (each part made once there)
            return installed_kinds, ()
        return Kinds, (list(self._by_name.values()),)

    def with_kinds(self, *more: Kind) -> Kinds:
        """This registry and more kinds."""
        return Kinds([*self.values(), *more])

    def check_targets(self) -> None:
        """Every [program.<kind>] table of every target belongs to one of these kinds and holds its keys."""
        for target in target_names():
            unknown = sorted(set(get_target(target).kind_tables) - set(self))
            if unknown:
                raise TargetFactsError(f"targets/{target}.toml: program.{unknown[0]}: no program kind of this name")
            for kind in self.values():
                _facts(kind, target)


@cache
def installed_kinds() -> Kinds:
    """The kinds the installed distributions register in the entry-point group `codegen.kinds` (codegen's own four
    in its pyproject.toml; another package's beside them), each target's kind tables checked against them."""
    found = [point.load() for point in entry_points(group=GROUP)]
    if not found:
        raise RuntimeError(f"no program kind in the entry-point group {GROUP!r}: reinstall codegen (pip install -e .)")
    kinds = Kinds(found)
    kinds.check_targets()
    return kinds
