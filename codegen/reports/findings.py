"""The neutral findings model every report format reads: per cell, a test case per target x program, its findings."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import asdict, dataclass, field, replace

LEVELS = ("error", "warning", "note")  # SARIF's result levels; JUnit and GitHub map them too


@dataclass(frozen=True)
class Location:
    """A place in a file: its path (as the command was given it, or repository-relative), 1-based line and column
    (0: the whole file, or the whole line)."""

    file: str
    line: int = 0
    column: int = 0


@dataclass(frozen=True)
class Finding:
    """One thing a reviewer should see: the rule it breaks (reports.rules), one sentence, its level, where in the
    program, and where in the cell file the value it comes from is written (the key's line), if it comes from one;
    `related`: further places that explain it (a hand-edited line behind a mismatch)."""

    rule: str
    message: str
    level: str
    program: Location | None = None
    cell: Location | None = None
    key: str | None = None  # the cell file's key path of `cell` (station[0].poses.chuck)
    related: tuple[Location, ...] = ()


@dataclass
class TestCase:
    """One cell x target x program: what ran (cases), how long (s), its findings and, where it failed, the text a
    test report shows (None: passed)."""

    __test__ = False  # not a pytest class

    cell: str
    target: str
    program: str
    files: list[str] = field(default_factory=list)
    cases: int = 0
    seconds: float = 0.0
    findings: list[Finding] = field(default_factory=list)
    failure: str | None = None
    output: str = ""  # further text beside the verdict (a hand edit's changed lines)
    error: str | None = None  # why it could not be done at all (a cell that does not load): None where it ran

    @property
    def failed(self) -> bool:
        return self.failure is not None


@dataclass
class CellResult:
    """One cell's results of one command (verify or check): its name, cell file (None: files without a cell) and
    test cases. A plant hands the writers many; one cell hands one."""

    command: str
    cell: str
    cell_file: str | None
    cases: list[TestCase] = field(default_factory=list)

    @property
    def findings(self) -> list[Finding]:
        return [f for case in self.cases for f in case.findings]

    def as_json(self) -> dict:
        return asdict(self)

    @classmethod
    def from_json(cls, data: dict) -> CellResult:
        """The inverse of as_json: a TypeError, KeyError or ValueError where it is not one."""
        cases = [TestCase(**{**case, "findings": [_finding(f) for f in case["findings"]]}) for case in data["cases"]]
        return cls(data["command"], data["cell"], data["cell_file"], cases)

    def moved(self, place: Callable[[str], str]) -> CellResult:
        """The same results with every file named by place(file): the cell file, each case's files and each place."""

        def at(where: Location | None) -> Location | None:
            return None if where is None else replace(where, file=place(where.file))

        def finding(f: Finding) -> Finding:
            return replace(f, program=at(f.program), cell=at(f.cell), related=tuple(at(r) for r in f.related))

        cases = [
            replace(case, files=[place(f) for f in case.files], findings=[finding(f) for f in case.findings])
            for case in self.cases
        ]
        return replace(self, cell_file=None if self.cell_file is None else place(self.cell_file), cases=cases)


def _location(data: dict | None) -> Location | None:
    return None if data is None else Location(**data)


def _finding(data: dict) -> Finding:
    related = tuple(Location(**r) for r in data["related"])
    return Finding(
        **{**data, "program": _location(data["program"]), "cell": _location(data["cell"]), "related": related}
    )
