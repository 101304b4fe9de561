"""Verify's report: a row per program (cases, mismatches, errors, arm margins, the kind's figures), text and JSON."""

from __future__ import annotations

import re
from array import array
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from codegen.controllers import get_target
from codegen.decimals import format_literal
from codegen.dialects import get_dialect
from codegen.protocol import Kind, VerifyPlan
from codegen.robot.expect import ArmStats

FIRST_MISMATCHES = 10  # how many mismatches a row names
# a case's numbers as its kind keeps them (a float's repr: 168.60999999999999) shown to 6 decimals, a millionth of a
# mm or deg, far below every tolerance; the seed, not the text, reproduces a case exactly
READING_DECIMALS = 6
_LONG_DECIMAL = re.compile(rf"(?<![\w.])-?\d+\.\d{{{READING_DECIMALS + 1},}}")


def readable(text: str) -> str:
    """text with every number of more than READING_DECIMALS decimals rounded to them (trailing zeros dropped)."""

    def rounded(match: re.Match) -> str:
        short = f"{float(match.group()):.{READING_DECIMALS}f}".rstrip("0").rstrip(".")
        return "0" if short in ("-0", "") else short

    return _LONG_DECIMAL.sub(rounded, text)


# mismatches whose numbers agree to a thousandth of a mm or deg (the tolerances are 0.005 mm and 0.001 deg) are one
# problem met in several cases: a hand edit moving a pose 20 mm is one line, whatever float32 adds in the millionths
ALIKE_DECIMALS = 3
_FINE_DECIMAL = re.compile(rf"(?<![\w.])-?\d+\.\d{{{ALIKE_DECIMALS + 1},}}")


# the move a problem is at, by its line: the same line's difference met at another move of the run (a loop's approach
# to each item, "move 8 (layer 1 box 1 approach, line 242)") is the same problem of the program
_MOVE_AT = re.compile(r"move \d+ \((?:[^()]*, )?(line \d+)\)")


def alike_key(problem: str) -> str:
    """The problem a mismatch is grouped by: its text with every number rounded to ALIKE_DECIMALS decimals."""
    return _FINE_DECIMAL.sub(lambda m: format_literal(float(m.group()), ALIKE_DECIMALS), problem)


_SETTING = re.compile(r"(?<=\): )(\w+)(?= )")  # a move's setting in a mismatch: "move 8 (approach, line 242): key"


def setting_names(target: str) -> dict[str, str]:
    """The target's move settings by its controller's names (its dialect's setting_names: an internal key by the
    system variable it stands for); {} where the settings' keys are the language's own words (a speed argument's)."""
    return getattr(get_dialect(get_target(target).dialect), "setting_names", {})


def controller_words(target: str, text: str) -> str:
    """text with the move setting a mismatch names written as the target's controller names it."""
    names = setting_names(target)
    return _SETTING.sub(lambda m: names.get(m.group(1), m.group(1)), text) if names else text


def case_text(kind, cell, case) -> str:
    """A case as the report names it: its category and the kind's description, numbers rounded for reading."""
    return readable(f"{getattr(case, 'category', 'case')} {kind.describe(cell, case)}".replace("  ", " ").strip())


@dataclass
class Replay:
    """A case a row keeps for the report page (Options.keep_replays): the report's words for it, its largest position
    (mm) and rotation (deg) error, where the arm started (deg), the trace, the reference's poses of the expectation it
    was compared with (4x4 mm each, None where the plan leaves a pose to the kind) and its mismatch (None: passed)."""

    what: str
    pos_max: float
    rot_max: float
    start_joints: object
    trace: object
    reference: list | None
    problem: str | None = None


@dataclass
class Row:
    """One program's results: its kind, target, name and files, the counts, every compared move's errors
    (8 bytes each), the first mismatches, the time spent running (one core), the arm's least margins and the
    kind's own figures (codegen.protocol.Figures), and the kind's verify plan that reads them."""

    kind: str
    target: str
    program: str
    files: list[str]
    cases: int = 0
    mismatches: int = 0
    halts: int = 0
    boundary: int = 0
    moves: int = 0
    swept: int = 0  # bulk ids (the station ids that are not stations, each shown to stop before moving)
    bulk_run: int = 0  # of those, the ids run (codegen.verify.bulk: one per class of the program's checks, a sample)
    pos_errors: array = field(default_factory=lambda: array("d"))
    rot_errors: array = field(default_factory=lambda: array("d"))
    first_mismatches: list[str] = field(default_factory=list)
    seconds: float = 0.0
    categories: dict[str, int] = field(default_factory=dict)
    scenarios: dict[str, int] = field(default_factory=dict)
    arm: ArmStats = field(default_factory=ArmStats)
    figures: object = None
    # the kind's verify plan (its JSON keys, its list, its report lines); None: a kind of that name without one
    verify: VerifyPlan | None = field(default=None, compare=False, repr=False)
    edits: list[str] = field(default_factory=list)  # a given program's changes against the generated one (edits.py)
    worst: Replay | None = None  # kept when asked: the passing case with the largest position error
    failed: Replay | None = None  # kept when asked: a mismatching case (the first of its chunk)

    alike: dict[str, int] = field(default_factory=dict)  # a shown mismatch's problem -> further cases with it
    alike_in: dict[str, list[str]] = field(default_factory=dict)  # a shown mismatch's problem -> its cases' categories
    # a problem with its move named by the line alone (_MOVE_AT) -> the shown problem it is counted with
    same_at_line: dict[str, str] = field(default_factory=dict, compare=False, repr=False)
    clearance: object = None  # the least clearance of the traces swept (codegen.verify.clearance.MoveLeast)
    clearance_traces: int = 0  # traces swept against the cell's solids
    clearance_seconds: float = 0.0  # the time the sweeps took (within `seconds`)

    @property
    def plan(self) -> VerifyPlan:
        return self.verify if self.verify is not None else Kind(self.kind).verify

    def mismatch(self, text: str, problem: str | None = None) -> None:
        """One case's mismatch: shown (the first FIRST_MISMATCHES problems, each once), or counted with the shown
        one of the same problem (`problem`: the text without the case, default the whole text)."""
        self.mismatches += 1
        category = text.split(" ", 1)[0]  # case_text starts with the case's category
        categories = [category] if category in self.categories else []
        self._show(controller_words(self.target, text), problem or text, 1, categories)

    def _show(self, text: str, problem: str, count: int, categories: list[str]) -> None:
        problem = self.same_at_line.setdefault(_MOVE_AT.sub(r"\1", problem), problem)
        if problem in self.alike:
            self.alike[problem] += count
        elif len(self.first_mismatches) < FIRST_MISMATCHES:
            self.first_mismatches.append(text)
            self.alike[problem] = count - 1
        else:
            return
        seen = self.alike_in.setdefault(problem, [])
        seen.extend(c for c in categories if c not in seen)

    def merge(self, part: Row) -> None:
        self.cases += part.cases
        self.mismatches += part.mismatches
        self.halts += part.halts
        self.boundary += part.boundary
        self.moves += part.moves
        self.swept += part.swept
        self.bulk_run += part.bulk_run
        self.pos_errors.extend(part.pos_errors)
        self.rot_errors.extend(part.rot_errors)
        problems = {text: problem for problem, text in zip(part.alike, part.first_mismatches, strict=True)}
        for text in part.first_mismatches:
            problem = problems[text]
            self._show(text, problem, part.alike[problem] + 1, part.alike_in.get(problem, []))
        self.seconds += part.seconds
        self.arm.merge(part.arm)
        for mine, theirs in ((self.categories, part.categories), (self.scenarios, part.scenarios)):
            for key, count in theirs.items():
                mine[key] = mine.get(key, 0) + count
        if part.worst is not None and (self.worst is None or part.worst.pos_max > self.worst.pos_max):
            self.worst = part.worst
        if self.failed is None:
            self.failed = part.failed
        if part.figures is not None:
            self.figures = part.figures if self.figures is None else self.figures + part.figures
        self.clearance_traces += part.clearance_traces
        self.clearance_seconds += part.clearance_seconds
        if part.clearance is not None and (self.clearance is None or part.clearance.distance < self.clearance.distance):
            self.clearance = part.clearance

    def summary(self) -> dict:
        """The row's JSON: the keys every row has, then the kind's own (its figures')."""

        def stats(values):
            if not values:
                return {"max": 0.0, "p99": 0.0}
            arr = np.frombuffer(values, dtype=float)
            return {"max": float(arr.max()), "p99": float(np.percentile(arr, 99))}

        out = {
            "kind": self.kind,
            "target": self.target,
            "program": self.program,
            "files": self.files,
            "cases": self.cases,
            "categories": self.categories,
            "scenarios": self.scenarios,
            "mismatches": self.mismatches,
            "halts": self.halts,
            "boundary_cases": self.boundary,
            "moves_compared": self.moves,
            "position_error_mm": stats(self.pos_errors),
            "orientation_error_deg": stats(self.rot_errors),
            "seconds": self.seconds,
            "cases_per_second": self.cases / self.seconds if self.seconds else None,
            "clearance_seconds": self.clearance_seconds,  # a row's time (plant.timing.ROW_TIMES), not in "clearance"
            "bulk_runs": self.swept,
            "bulk_ids_run": self.bulk_run,
        }
        if self.arm.moves:
            out["arm"] = self.arm.summary()
        if self.clearance is not None:
            least = self.clearance
            out["clearance"] = {"traces": self.clearance_traces, "least_mm": least.distance,
                                "at_least_mm": least.lower_bound, "move": least.where, "what": least.what,
                                "body": least.body, "other": least.other}
        out.update(self.plan.figures_json(self.figures))
        out["first_mismatches"] = self.first_mismatches
        out["mismatches_alike"] = [self.alike[p] for p in self.alike]  # per first mismatch: further cases alike
        out["edits"] = self.edits
        return out


@dataclass
class Report:
    """verify_cell's result: the cell, a row per program, what was run and how long it took (wall)."""

    cell: str
    rows: list[Row]
    seed: int
    cases: int
    wall_seconds: float = 0.0
    workers: int = 1
    warnings: list[str] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        return bool(self.rows) and all(r.mismatches == 0 for r in self.rows)

    def margin_warnings(self) -> list[str]:
        """A program whose runs came nearer a joint limit, or the wrist singularity, than the cell asks (the cell's
        requirement of every move, whatever the case): one line each, naming the move and the case."""
        out = []
        for row in self.rows:
            for short in (row.arm.shortfall(), row.arm.wrist_shortfall()):
                if short is not None:
                    out.append(f"arm {row.target} {row.program}: {short}")
        return out

    def as_json(self) -> dict:
        """Every row under "programs"; each kind's rows also under the kind's own key (VerifyPlan.report_key), as its
        list has them (VerifyPlan.listed)."""
        out = {
            "cell": self.cell,
            "seed": self.seed,
            "random_per_station": self.cases,
            "ok": self.ok,
            "wall_seconds": self.wall_seconds,
            "workers": self.workers,
            "programs": [r.summary() for r in self.rows],
        }
        for row in self.rows:
            key = row.plan.report_key or f"{row.kind}s"
            out.setdefault(key, []).append(row.plan.listed_row(row.summary()))
        return out

    def header(self) -> str:
        count = len(self.rows)
        return f"cell {self.cell}: {count} program{'' if count == 1 else 's'} (seed {self.seed})"

    def lines(self) -> list[str]:
        """The text report: one line per program, its first mismatches, each kind's own table, the arm's margins,
        the runs and the verdict."""
        out = [self.header()]
        out.append(
            f"{'program':<26}{'kind':<9}{'target':<7}{'cases':>7}{'fail':>6}{'halts':>7}{'bound':>7}{'pos max mm':>11}"
            f"{'pos p99':>10}{'rot max deg':>12}{'rot p99':>10}{'cases/s':>8}"
        )
        for row in self.rows:
            s = row.summary()
            out.append(
                f"{_fit(row.program, 25):<26}{row.kind:<9}{row.target:<7}{s['cases']:>7}{s['mismatches']:>6}"
                f"{s['halts']:>7}{s['boundary_cases']:>7}{s['position_error_mm']['max']:>11.2e}"
                f"{s['position_error_mm']['p99']:>10.2e}{s['orientation_error_deg']['max']:>12.2e}"
                f"{s['orientation_error_deg']['p99']:>10.2e}{_rate(s['cases_per_second']):>8}"
            )
            if len({Path(f).name for f in row.files}) and any(not f.startswith("<fresh>") for f in row.files):
                out.append(f"  files: {', '.join(row.files)}")
            out.extend(f"  {line}" for line in row.edits)
            for line, (problem, alike) in zip(row.first_mismatches, row.alike.items(), strict=True):
                categories = row.alike_in.get(problem, [])
                among = f"; in {', '.join(categories)}" if len(categories) > 1 else ""
                out.append(f"  MISMATCH {line}" + (f" (and {alike} more cases alike{among})" if alike else ""))
        kinds = {row.kind: row.plan for row in self.rows}
        for kind, plan in kinds.items():
            out.extend(plan.report_lines([row for row in self.rows if row.kind == kind]))
        for row in self.rows:
            if row.arm.moves:
                arm = row.arm.summary()
                # the runner adds a run's moves only where the run matches: a failing program's margins are its
                # matching runs', and the line says so
                counted = f" in the runs that match (not the {row.mismatches} that mismatch)" if row.mismatches else ""
                out.append(
                    f"arm {row.target} {row.program}: {arm['moves']} moves solved to joints{counted}; least margin "
                    f"to a joint limit {arm['joint_margin_deg']:.1f} deg ({arm['joint_margin_at']}), of axis 5 from "
                    f"its singularity {arm['wrist_margin_deg']:.1f} deg"
                )
        for row in self.rows:
            if row.clearance is not None:
                least = row.clearance
                out.append(
                    f"clearance {row.target} {row.program}: {row.clearance_traces} traces swept; least "
                    f"{least.distance:.1f} mm ({least.body} - {least.other}) at {least.where}, the {least.what}"
                )
        runs = sum(r.cases for r in self.rows)
        bulk = sum(r.swept for r in self.rows)
        extra = f" and {bulk} bulk ids ({sum(r.bulk_run for r in self.rows)} run)" if bulk else ""
        out.append(
            f"{runs} runs{extra} in {self.wall_seconds:.1f} s wall, {self.workers} worker(s); cases/s = one program "
            "on one core"
        )
        out.append("verify: all traces match the reference" if self.ok else "verify: MISMATCHES")
        return out


def _fit(text: str, width: int) -> str:
    return text if len(text) <= width else text[: width - 3] + "..."


def _rate(per_second: float | None) -> str:
    """Cases per second for the table: a slow kind (a whole cycle per case) keeps its first figures."""
    if not per_second:
        return "0"
    return f"{per_second:.0f}" if per_second >= 100 else f"{per_second:.3g}"
