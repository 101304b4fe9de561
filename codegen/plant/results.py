"""A plant's results: a row per cell and target (cell, target, kind, cases, result, time), its text table, its JSON
(what was found: no times) and its times, and the exit code they make."""

from __future__ import annotations

from dataclasses import asdict, dataclass, field

from codegen.plant.timing import split

EXIT_OK, EXIT_DIFFERS, EXIT_BAD = 0, 1, 2
COLUMNS = ("cell", "target", "kind")  # the text columns as wide as their longest entry
# a result word and the exit code it makes; a cached result keeps its verdict ("cached" = a cached pass)
RESULTS = {
    "ok": EXIT_OK,
    "written": EXIT_OK,
    "clean": EXIT_OK,
    "cached": EXIT_OK,
    "skipped": EXIT_OK,
    "mismatch": EXIT_DIFFERS,
    "cached mismatch": EXIT_DIFFERS,
    "differs": EXIT_DIFFERS,
    "findings": EXIT_DIFFERS,
    "error": EXIT_BAD,
}


@dataclass
class Line:
    """One row of the table: a cell's result for one target (or for all of them: target "*")."""

    cell: str
    target: str
    kind: str
    cases: int | None
    result: str
    seconds: float
    message: str = ""

    def __post_init__(self):
        if self.result not in RESULTS:
            raise ValueError(f"unknown result {self.result!r}")


@dataclass
class CellResult:
    """One cell's rows, the command's own JSON for it (verify's report, generate's files, ...), whether it came
    from the cache, and (verify, check) its findings for the report formats (reports.findings.CellResult's JSON, its
    files relative to the plant's folder)."""

    cell: str
    name: str
    lines: list[Line]
    data: dict | None = None
    cached: bool = False
    notes: list[str] = field(default_factory=list)
    findings: dict | None = None
    # verify's warnings about the runs (a joint or wrist margin short of the cell's: Report.margin_warnings), printed
    # as the single cell's verify prints them
    warnings: list[str] = field(default_factory=list)

    @property
    def exit_code(self) -> int:
        return max((RESULTS[line.result] for line in self.lines), default=EXIT_OK)

    def as_json(self) -> dict:
        """Everything, times too (a cache entry)."""
        return {
            "cell": self.cell,
            "name": self.name,
            "cached": self.cached,
            "exit": self.exit_code,
            "rows": [asdict(line) for line in self.lines],
            "notes": self.notes,
            "warnings": self.warnings,
            "data": self.data,
            "findings": self.findings,
        }

    def report(self) -> tuple[dict, dict]:
        """(its entry in the plant's report: as_json without the times, its times: the rows' and the data's)."""
        data, data_times = split(self.data)
        found = {k: v for k, v in self.as_json().items() if k != "findings"}  # the formats' (--format) alone
        found.update(rows=[_untimed(line) for line in self.lines], data=data)
        times = {"cell": self.cell, "rows": [{"target": line.target, "seconds": line.seconds} for line in self.lines]}
        return found, {**times, "data": data_times} if data_times else times

    @classmethod
    def from_json(cls, data: dict) -> CellResult:
        """The inverse of as_json (a cache entry): a TypeError, KeyError or ValueError where it is not one."""
        lines = [Line(**row) for row in data["rows"]]
        cached, notes = bool(data["cached"]), list(data["notes"])
        warnings = list(data.get("warnings", []))  # an entry stored before warnings were kept has none
        return cls(data["cell"], data["name"], lines, data["data"], cached, notes, data["findings"], warnings)


def _untimed(line: Line) -> dict:
    return {k: v for k, v in asdict(line).items() if k != "seconds"}


def cell_kinds(cell) -> str:
    """The table's kind column: the program kinds of a cell's sections, in the registry's order."""
    return ",".join(cell.sections)


def error_result(cell: str, message: str, seconds: float = 0.0, name: str = "") -> CellResult:
    """A cell that could not be done: its one row says why."""
    return CellResult(cell, name, [Line(cell, "*", "", None, "error", seconds, message)])


@dataclass
class PlantReport:
    """Every cell's result, in the plant's order, for one command."""

    command: str
    plant: str
    results: list[CellResult]
    seconds: float
    notes: list[str] = field(default_factory=list)

    @property
    def exit_code(self) -> int:
        """2 when a cell could not be done, else 1 when one differs (mismatch, diff, findings), else 0."""
        return max((r.exit_code for r in self.results), default=EXIT_OK)

    def counts(self) -> dict[str, int]:
        out: dict[str, int] = {}
        for result in self.results:
            for line in result.lines:
                out[line.result] = out.get(line.result, 0) + 1
        return out

    def as_json(self) -> dict:
        """What was found, without the times: the same plant, options and seed give the same JSON on any machine,
        cluster or number of workers."""
        return {
            "command": self.command,
            "plant": self.plant,
            "exit": self.exit_code,
            "counts": self.counts(),
            "notes": self.notes,
            "rows": [_untimed(line) for r in self.results for line in r.lines],
            "cells": [r.report()[0] for r in self.results],
        }

    def timings(self) -> dict:
        """How long it took: the whole run, each cell's rows and (verify) its run's figures (for a cached cell, those
        of the run that stored it), in the cells' order."""
        return {
            "command": self.command,
            "plant": self.plant,
            "seconds": self.seconds,
            "cells": [r.report()[1] for r in self.results],
        }

    def lines(self) -> list[str]:
        rows = [line for r in self.results for line in r.lines]
        cell, target, kind = (max([len(title), *(len(getattr(line, title)) for line in rows)]) for title in COLUMNS)
        out = [f"plant {self.plant}: {len(self.results)} cells ({self.command})"]
        out.append(f"{'cell':<{cell}}  {'target':<{target}}  {'kind':<{kind}}  {'cases':>7}  {'result':<16}{'time':>9}")
        for line in rows:
            cases = "" if line.cases is None else str(line.cases)
            out.append(
                f"{line.cell:<{cell}}  {line.target:<{target}}  {line.kind:<{kind}}  {cases:>7}  {line.result:<16}"
                f"{line.seconds:>7.1f} s"
            )
            out.extend(f"  {text}" for text in line.message.splitlines() if text)
        for result in self.results:
            out.extend(f"warning: {result.cell}: {warning}" for warning in result.warnings)
            out.extend(f"note: {result.cell}: {note}" for note in result.notes)
        out.extend(f"note: {note}" for note in self.notes)
        shown = ", ".join(f"{n} {word}" for word, n in self.counts().items())
        out.append(f"{len(rows)} rows: {shown}; {self.seconds:.1f} s")
        return out
