"""A plant's results: a row per cell and target (cell, target, kind, cases, result, time), its text table and JSON,
and the exit code they make."""

from __future__ import annotations

from dataclasses import asdict, dataclass, field

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
    """One cell's rows, the command's own JSON for it (verify's report, generate's files, ...) and whether it came
    from the cache."""

    cell: str
    name: str
    lines: list[Line]
    data: dict | None = None
    cached: bool = False
    notes: list[str] = field(default_factory=list)

    @property
    def exit_code(self) -> int:
        return max((RESULTS[line.result] for line in self.lines), default=EXIT_OK)

    def as_json(self) -> dict:
        return {
            "cell": self.cell,
            "name": self.name,
            "cached": self.cached,
            "exit": self.exit_code,
            "rows": [asdict(line) for line in self.lines],
            "notes": self.notes,
            "data": self.data,
        }

    @classmethod
    def from_json(cls, data: dict) -> CellResult:
        """The inverse of as_json (a cache entry): a TypeError, KeyError or ValueError where it is not one."""
        lines = [Line(**row) for row in data["rows"]]
        return cls(data["cell"], data["name"], lines, data["data"], bool(data["cached"]), list(data["notes"]))


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
        return {
            "command": self.command,
            "plant": self.plant,
            "exit": self.exit_code,
            "seconds": self.seconds,
            "counts": self.counts(),
            "notes": self.notes,
            "rows": [asdict(line) for r in self.results for line in r.lines],
            "cells": [r.as_json() for r in self.results],
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
            out.extend(f"note: {result.cell}: {note}" for note in result.notes)
        out.extend(f"note: {note}" for note in self.notes)
        shown = ", ".join(f"{n} {word}" for word, n in self.counts().items())
        out.append(f"{len(rows)} rows: {shown}; {self.seconds:.1f} s")
        return out
