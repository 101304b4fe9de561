"""What a change to a cell's programs does: each program on disk (the old side) and fresh from the cell (the new)
run on the same nominal cases, their traces compared (poses, settings, I/O, messages, stops, counters, time)."""

from __future__ import annotations

import difflib
import math
import re
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

from codegen.controllers import get_target
from codegen.dialects.core.files import SourceFile
from codegen.dialects.core.machine import DEFAULT_STEP_LIMIT
from codegen.dialects.core.trace import halt_text
from codegen.dialects.core.values import RunError
from codegen.output import written_by_codegen
from codegen.render import cell_dir
from codegen.verify.checks import TOLERANCES, Checker, pose_errors
from codegen.verify.plan import SCENARIOS
from codegen.verify.programs import ProgramSource, fresh_sources
from codegen.verify.report import Row

RUNS = 32  # nominal runs compared per program: the kind's first category (a station each), from home
HOME_MOVES = 1  # moves a run may make before it reaches its station (the way home first), none of the station's
TIME_STEP_S = 1e-6  # clocks closer than this are the same time (both sum the same float64 terms)


@dataclass
class ProgramChange:
    """One program's change: its target, name, status (changed, added, removed), its files (paths under the
    output folder), what its runs show, grouped, what the runs could not tell, the raw unified diff and the new
    program's verify verdict (None: not verified)."""

    target: str
    program: str
    status: str
    files: list[str] = field(default_factory=list)
    stations: list[str] = field(default_factory=list)  # what the old program serves and the new does not, or back
    moved: list[str] = field(default_factory=list)
    largest_move: tuple[float, float] = (0.0, 0.0)  # mm, deg
    settings: list[str] = field(default_factory=list)
    io: list[str] = field(default_factory=list)
    messages: list[str] = field(default_factory=list)
    stops: list[str] = field(default_factory=list)
    counters: list[str] = field(default_factory=list)
    motion: list[str] = field(default_factory=list)  # moves added or removed, the run's time
    other: list[str] = field(default_factory=list)
    changed_lines: int = 0
    changed_files: list[str] = field(default_factory=list)  # the names of its files that differ (it has several)
    raw: str = ""
    ident: str = ""
    verdict: str | None = None
    passed: bool | None = None

    GROUPS = (
        ("stations", "stations added or removed"),
        ("moved", "poses moved"),
        ("settings", "speeds, zones, tools"),
        ("io", "I/O"),
        ("messages", "messages"),
        ("stops", "stops"),
        ("counters", "counters and stored values"),
        ("motion", "moves and time"),
        ("other", "other changes"),
    )


@dataclass
class CellChange:
    cell: str
    cell_file: str | None
    programs: list[ProgramChange] = field(default_factory=list)
    verify: str | None = None  # the verdict of all the new programs (None: not verified)


def cell_change(cell, out_dir: Path, seed: int = 0) -> CellChange:
    """The change from the programs under out_dir to the cell's fresh ones, per program (unchanged ones left out)."""
    out = CellChange(cell.name, cell.source or None)
    produced: set[Path] = set()
    for target_name in cell.targets:
        for new in fresh_sources(cell, [target_name]):
            paths = [out_dir / f.name.removeprefix("<fresh>/") for f in new.files]
            produced.update(paths)
            old_files = [SourceFile(str(p), p.read_text(encoding="utf-8")) for p in paths if p.is_file()]
            raw = _raw(paths, new)
            if not raw:
                continue
            name = Path(paths[0]).name
            status = "added" if not old_files else "changed"
            change = ProgramChange(target_name, name, status, [str(p) for p in paths], raw=raw, ident=new.ident)
            change.changed_lines = sum(
                1 for line in raw.splitlines() if line[:1] in "+-" and not line.startswith(("+++", "---"))
            )
            if len(paths) > 1:
                change.changed_files = [p.name for p, f in zip(paths, new.files, strict=True) if _text(p) != f.text]
            if old_files:
                _compare(cell, new, old_files, paths, change, seed)
            out.programs.append(change)
        folder = out_dir / cell_dir(cell) / target_name
        for extra in sorted(folder.glob("*")) if folder.is_dir() else []:
            if extra.is_file() and extra not in produced and written_by_codegen(extra):
                gone = ProgramChange(target_name, extra.name, "removed", [str(extra)])
                gone.other.append("not generated any more (the cell has no program or file of this name)")
                out.programs.append(gone)
    return out


def _text(path: Path) -> str:
    return path.read_text(encoding="utf-8") if path.is_file() else ""


def _raw(paths: list[Path], new: ProgramSource) -> str:
    chunks = []
    for path, fresh in zip(paths, new.files, strict=True):
        old = _text(path)
        if old != fresh.text:
            chunks += difflib.unified_diff(
                old.splitlines(keepends=True),
                fresh.text.splitlines(keepends=True),
                fromfile=str(path) if path.is_file() else "/dev/null",
                tofile=f"{path} (fresh)",
            )
    return "".join(chunks)


def _compare(cell, new: ProgramSource, old_files: list[SourceFile], paths: list[Path], change, seed: int) -> None:
    """Both programs run on the kind's nominal cases; every difference of their traces, each said once."""
    main = next((f for f in old_files if f.name == str(paths[0])), None)
    if main is None:
        change.other.append(
            f"{paths[0].name} is new: the old side has only {', '.join(Path(f.name).name for f in old_files)}"
        )
        return
    ordered = (main, *(f for f in old_files if f is not main))
    old = ProgramSource(
        new.kind, new.target, new.ident, new.index, ordered, tuple(f.name for f in ordered), entry=new.entry
    )
    try:
        programs = (old.load(), new.load())
    except RunError as exc:
        change.other.append(f"not compared by running: {exc}")
        return
    kind = cell.kinds[new.kind].verify
    cases = [c for c in kind.cases(cell, new, 1, seed) if c.start == "home" and c.scenario not in SCENARIOS]
    cases = [c for c in cases if c.category == cases[0].category][:RUNS] if cases else []
    arm = Checker(cell, new.target).arm
    tolerance = TOLERANCES[get_target(new.target).numbers]
    said: dict[str, dict[str, None]] = {name: {} for name, _ in ProgramChange.GROUPS}
    largest = [0.0, 0.0]
    for case in cases:
        traces = []
        for program in programs:
            setup = kind.setup(cell, new, case)  # each run its own simulated devices: they keep state
            try:
                traces.append(program.run(setup.inputs, **setup.run_options(arm, None)))
            except RunError as exc:
                traces.append(exc)
        where = f"{case.category} {kind.describe(cell, case)}".strip()
        for group, text in _differences(*traces, where, tolerance, largest, len(new.files) > 1):
            said[group].setdefault(text, None)
    for text in _removed(cell, new, programs[0], change.raw):
        said["stations"].setdefault(text, None)
    for name, _ in ProgramChange.GROUPS:
        getattr(change, name).extend(said[name])
    change.largest_move = (largest[0], largest[1])
    if not any(said.values()):
        change.other.append(
            f"{change.changed_lines} changed lines that change nothing in {len(cases)} nominal runs (comments, "
            "branches those runs do not take, names)"
        )


def _differences(
    old, new, where: str, tolerance: tuple[float, float], largest: list, files: bool = False
) -> list[tuple[str, str]]:
    """(group, sentence) of each difference of the new run from the old on one case; files: the program is several
    files, each move's line named with its file's."""
    if isinstance(old, RunError) or isinstance(new, RunError):
        if isinstance(new, RunError) and not isinstance(old, RunError):
            return [("stops", f"{where}: the new program stops with an error: {new}")]
        if isinstance(old, RunError) and not isinstance(new, RunError):
            return [("stops", f"{where}: the old program stopped with an error, the new one runs: {old}")]
        return []
    out = []
    if old.halted and not new.halted and len(old.moves) <= HOME_MOVES < len(new.moves):
        text = (
            f"{where}: added (the old program stops before it moves there: {halt_text(old)!r}; the new one serves it)"
        )
        return [("stations", text)]
    if old.halted != new.halted or (new.halted and old.halt_message != new.halt_message):
        was = f"stopped ({halt_text(old)!r})" if old.halted else "ran on"
        now = f"stops ({halt_text(new)!r})" if new.halted else "runs on"
        out.append(("stops", f"{where}: the new program {now}; the old one {was}"))
    if len(old.moves) != len(new.moves):
        out.append(("motion", f"{where}: {len(new.moves)} moves, were {len(old.moves)}"))
    for i, (a, b) in enumerate(zip(old.moves, new.moves, strict=False)):
        at = f"{Path(b.file).name} line {b.line}" if files and b.file else f"line {b.line}"
        if a.tcp2base is not None and b.tcp2base is not None:
            mm, deg = pose_errors(a.tcp2base.tolist(), b.tcp2base.tolist())
            if mm > tolerance[0] or deg > tolerance[1]:
                largest[0], largest[1] = max(largest[0], mm), max(largest[1], deg)
                out.append(("moved", f"move {i + 1} ({at}) in {where}: {mm:.3f} mm, {deg:.3f} deg"))
        for key in sorted(set(a.settings) | set(b.settings)):
            was, now = _plain(a.settings.get(key)), _plain(b.settings.get(key))
            if was != now:
                out.append(("settings", f"move {i + 1} ({at}): {key} {_shown(now)}, was {_shown(was)}"))

    def key(e):
        return (e.name, e.value, e.after_moves)

    for n, v, k in Counter(map(key, new.outputs)) - Counter(map(key, old.outputs)):
        out.append(("io", f"sets {n} {v} after move {k} (new)"))
    for n, v, k in Counter(map(key, old.outputs)) - Counter(map(key, new.outputs)):
        out.append(("io", f"no longer sets {n} {v} after move {k}"))
    out += [("messages", f"writes {m!r} (new)") for m in Counter(new.messages) - Counter(old.messages)]
    out += [("messages", f"no longer writes {m!r}") for m in Counter(old.messages) - Counter(new.messages)]
    for name in sorted(set(old.kept) | set(new.kept)):
        if _plain(old.kept.get(name)) != _plain(new.kept.get(name)):
            was, now = _shown(old.kept.get(name)), _shown(new.kept.get(name))
            out.append(("counters", f"{name} ends at {now}, was {was} ({where})"))
    total = new.clock - old.clock
    if abs(total) > TIME_STEP_S and math.isfinite(total):
        out.append(("motion", f"{where}: the run takes {new.clock:.2f} s, was {old.clock:.2f} s"))
    return out


def _removed(cell, new: ProgramSource, old_program, raw: str) -> list[str]:
    """What the old program serves that is no station of the cell now: the kind's sweep (every id that is no station
    must stop before it moves) run on the old program for the numbers of the lines the change removes (a removed
    station's dispatch is among them), where the kind sweeps ids at all."""
    kind = cell.kinds[new.kind].verify
    ranges = kind.sweeps(cell, new, 1)
    removed = "\n".join(line for line in raw.splitlines() if line.startswith("-") and not line.startswith("---"))
    ids = sorted({n for n in map(int, re.findall(r"\b\d+\b", removed)) if any(n in r for r in ranges)})
    if not ids:
        return []
    row = Row(new.kind, new.target, new.ident, [], verify=kind)
    try:
        kind.sweep(cell, new, old_program, ids, DEFAULT_STEP_LIMIT, row, every=True)  # each id: the old text names them
    except RunError as exc:
        return [f"not swept: {exc}"]
    more = row.mismatches - len(row.first_mismatches)
    said = [f"removed (the old program serves it, the new one stops): {text}" for text in row.first_mismatches]
    return said + ([f"... and {more} more ids the old program serves"] if more > 0 else [])


def _plain(value):
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items() if k != "line"}  # where a setting was written is the diff's
    if hasattr(value, "tolist"):
        return value.tolist()
    return value


def _shown(value) -> str:
    value = _plain(value)
    if value is None:
        return "not set"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k} {_shown(v)}" for k, v in value.items()) + "}"
    if isinstance(value, list | tuple):
        return "[" + ", ".join(_shown(v) for v in value) + "]"
    if isinstance(value, float):
        return f"{value:g}"
    return str(value)


def add_verdicts(change: CellChange, report) -> None:
    """verify's verdict of the new programs (its Report of the fresh programs), per program and for the cell."""
    rows = {(row.target, row.program): row for row in report.rows}
    for program in change.programs:
        row = rows.get((program.target, program.ident))
        if row is not None:
            program.passed = row.mismatches == 0
            program.verdict = (
                f"{row.mismatches} of {row.cases} cases mismatch" if row.mismatches else f"{row.cases} cases"
            )
    runs = sum(row.cases for row in report.rows)
    failed = sum(row.mismatches for row in report.rows)
    change.verify = (
        f"all {len(report.rows)} programs match the reference ({runs} cases, seed {report.seed})"
        if report.ok
        else f"MISMATCHES: {failed} of {runs} cases in {sum(r.mismatches > 0 for r in report.rows)} programs"
    )
