"""Programs for the tests: a cell's fresh programs as sources, edited copies, and the engine's rows for them."""

from __future__ import annotations

import re
from dataclasses import replace

from codegen.dialects.core.files import SourceFile
from codegen.verify.engine import Options, verify_sources
from codegen.verify.programs import ProgramSource, fresh_sources


def sources(cell, target: str, kind: str | None = None) -> list[ProgramSource]:
    """The cell's fresh programs for one target (of one kind, if given), in the registry's order."""
    return [s for s in fresh_sources(cell, [target]) if kind is None or s.kind == kind]


def first(cell, target: str, kind: str | None = None) -> ProgramSource:
    return sources(cell, target, kind)[0]


def edited(source: ProgramSource, edit, label: str = "edited") -> ProgramSource:
    """A copy of the program with edit(text) applied to each of its files' texts (edit returns the text, changed or
    not); the edit must change some file."""
    files = tuple(SourceFile(f"{label}/{f.name.rsplit('/', 1)[-1]}", edit(f.text)) for f in source.files)
    assert [f.text for f in files] != [f.text for f in source.files], f"{label}: the edit changed nothing"
    return replace(source, files=files, origin=tuple(f.name for f in files))


def regex_edit(pattern: str, replacement, count: int = 1):
    """An edit: the first match of the pattern in the first file that has one (count 0: every match in every file;
    re.MULTILINE)."""
    done = []

    def edit(text: str) -> str:
        if done and count:
            return text
        new, found = re.subn(pattern, replacement, text, count=count, flags=re.MULTILINE)
        if found:
            done.append(True)
        return new

    return edit


def verify(
    cell,
    source_list,
    cases: int = 3,
    seed: int = 0,
    first_mismatch: bool = False,
    sweeps: bool = False,
    scenarios=None,
    clearance: bool = True,
):
    """The engine's rows for the programs (in this process; the kinds' bulk runs only when asked; only the cases
    of the scenarios named, if any; clearance=False: no trace swept against the cell's solids, for a test that asks
    only whether an edit's own difference fails verify)."""
    options = Options(
        cases, seed, 1, first_mismatch=first_mismatch, sweeps=sweeps, scenarios=scenarios, clearance=clearance
    )
    rows, _ = verify_sources(cell, list(source_list), options)
    return rows


def verify_one(cell, source: ProgramSource, **options):
    return verify(cell, [replace(source, row=0)], **options)[0]


def load_program(target, text: str, filename: str = "program", companions: dict | None = None):
    """A program from its text (and its data files by suffix), for the interpreter's own tests."""
    from codegen.dialects.core.files import SourceFile
    from codegen.verify.programs import load_files

    stem = filename.rsplit(".", 1)[0]
    rest = [SourceFile(stem + suffix, body) for suffix, body in (companions or {}).items()]
    return load_files(target, [SourceFile(filename, text), *rest], filename)


def run_case(cell, target: str, program, case, kind: str):
    """One of a kind's cases run on a loaded program, set up as verify sets it up: (trace, setup)."""
    from codegen.robot.expect import arm_of

    source = first(cell, target, kind)
    setup = cell.kinds[kind].verify.setup(cell, source, case)
    return program.run(setup.inputs, **setup.run_options(arm_of(cell, target), 2_000_000)), setup
