"""Verify's sections for programs of their own (a conveyor's, a laser station's): fresh programs, files, report."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from codegen.controllers import get_target


def fresh_program(cell, target_name: str, names: list[str]):
    """The program in files `names` (the main one first, a data file beside it) rendered from the cell and
    parsed: (program, names)."""
    from codegen.render import render
    from codegen.verify_runs import load_program

    target = get_target(target_name)
    files = {f.relpath.rsplit("/", 1)[1]: f for f in render(cell, [target_name])}
    main = files[names[0]]
    companions = {"." + n.rsplit(".", 1)[1]: files[n].text for n in names[1:]}
    return load_program(target, main.text, f"<fresh>/{main.relpath}", companions), names


def collect(
    cell,
    files: tuple,
    targets: tuple,
    own_names: Callable[[object], list[str]],
    fresh: Callable[[object, str], tuple | None],
    verify: Callable[..., object],
) -> tuple[list, tuple]:
    """Each target's program among FILES (named as the section's programs: own_names(target)), or its fresh
    one when no files are given, verified (verify(cell, target name, program, file names)); the reports and
    the files that are not this section's."""
    from codegen.verify_runs import file_source

    reports, rest = [], list(files)
    for name in list(targets) or list(cell.targets):
        own = own_names(get_target(name))
        if files:
            for f in [f for f in rest if Path(f).name in own]:
                rest.remove(f)  # a data file is read with its program (file_source)
                if Path(f).name == own[0]:
                    source = file_source(name, Path(f))
                    reports.append(verify(cell, name, source.load(), list(source.files)))
            continue
        found = fresh(cell, name)
        if found is not None:
            reports.append(verify(cell, name, *found))
    return reports, tuple(rest)


@dataclass
class SectionReport:
    """One target's report in a section: the counts every section keeps, its own figures (figures())
    between them in the JSON summary."""

    target: str
    files: list[str]
    cases: int = 0
    mismatches: int = 0
    max_pos_mm: float = 0.0  # the largest difference from the reference
    max_rot_deg: float = 0.0
    first_mismatches: list[str] = field(default_factory=list)
    seconds: float = 0.0

    def figures(self) -> dict:
        return {}

    def summary(self) -> dict:
        head = {"target": self.target, "files": self.files, "cases": self.cases, "mismatches": self.mismatches}
        return {**head, **self.figures(), "first_mismatches": self.first_mismatches}


class Reports:
    """A section's reports (each with target, cases, mismatches, first_mismatches and summary()): all matched,
    their JSON summaries."""

    reports: list

    @property
    def ok(self) -> bool:
        return all(r.mismatches == 0 for r in self.reports)

    def summaries(self) -> list[dict]:
        return [r.summary() for r in self.reports]


@dataclass
class Section(Reports):
    """Reports with their table's header, a row per report (row(report)) and the verdicts."""

    reports: list
    header: str
    row: Callable[[object], str]
    passed: str
    failed: str

    def lines(self) -> list[str]:
        lines = [self.header]
        for r in self.reports:
            lines.append(self.row(r))
            lines += [f"  {r.target}: {m}" for m in r.first_mismatches]
        return [*lines, f"verify: {self.passed if self.ok else self.failed}"]
