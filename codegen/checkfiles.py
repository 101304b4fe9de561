"""Every finding of program files, as `codegen check` reports them (the command and a plant's check both use it)."""

from __future__ import annotations

import inspect
from collections.abc import Callable
from dataclasses import dataclass

from codegen.cli_base import UserError
from codegen.cli_run import program_files, program_groups

EXIT_CLEAN, EXIT_FINDINGS, EXIT_REFUSED = 0, 1, 2  # refused: a file does not parse or uses what is not modelled


def _by_language(paths: tuple[str, ...], target_name: str | None) -> list[tuple[str, ...]]:
    """The paths given, split by language where no --target names one (a folder of several controllers'
    programs): each part's files, in the order given; a folder's files of one language together."""
    from pathlib import Path

    from codegen.dialects import dialect_of_suffix

    if target_name is not None:
        return [paths]
    parts: dict[str, list[str]] = {}
    for text in paths:
        path = Path(text)
        found = sorted(p for p in path.rglob("*") if p.is_file()) if path.is_dir() else [path]
        for file in found:
            dialect = dialect_of_suffix(file.suffix)
            if dialect is None and not path.is_dir():
                raise UserError(f"{file}: cannot tell the target from the suffix; use --target")
            if dialect is not None:
                parts.setdefault(dialect.name, []).append(str(file))
    if not parts:
        raise UserError(f"{paths[0]}: no program files here")
    if len(parts) == 1:
        return [paths]  # as given: a single program file brings its data files
    return [tuple(files) for files in parts.values()]


def _check_group(dialect, group, options) -> list:
    """Dialect.check_files of one program, with the options where the dialect's override takes them."""
    from codegen.dialects.core.files import finding_of

    takes_options = "options" in inspect.signature(dialect.check_files).parameters
    try:
        return dialect.check_files(group, options=options) if takes_options else dialect.check_files(group)
    except RecursionError:
        return [finding_of(f"{group[0].name}: statements or expressions nested too deeply", group)]


@dataclass
class Checked:
    """check_files' result: the files, their programs, every finding (in file order), the counts by severity, the
    exit code, the targets' titles and names, and each program as (target, its file names)."""

    sources: list
    groups: list
    findings: list
    counts: dict[str, int]
    code: int
    titles: list[str]
    names: list[str]
    programs: list[tuple[str, list[str]]]


def check_files(
    files: tuple[str, ...],
    target_name: str | None,
    arm=None,
    robot: str | None = None,
    entry_of: Callable[[list[str]], str | None] | None = None,
) -> Checked:
    """Every finding of the files (and folders) given, as `codegen check` reports them; UserError for a file that
    is no program of a language or an arm of another controller. entry_of: a program's file names -> the routine
    it starts at, where its language lets a program start at one of its own (None: its main)."""
    from codegen.dialects.core.kept import STORE

    with STORE.keeping():  # each file parsed once: its syntax, the linker and the field checks read the same tree
        return _check_files(files, target_name, arm, robot, entry_of)


def _check_files(files, target_name, arm, robot, entry_of) -> Checked:
    from codegen.dialects.core.files import SEVERITIES, CheckOptions, Finding

    sources, groups, findings, titles, names, programs = [], [], [], [], [], []
    for language_paths in _by_language(files, target_name):
        target, dialect, language_sources = program_files(language_paths, target_name)
        if arm is not None and arm.vendor != target.vendor:
            raise UserError(
                f"--robot {robot or arm.model!r}: an arm of the {arm.vendor} controller; these files are for "
                f"{target.name}"
            )
        sources += language_sources
        titles.append(target.title)
        names.append(target.name)
        try:
            language_groups = program_groups(dialect, language_sources)
        except UserError as exc:  # a data file without its program: a finding like the others
            language_groups = []
            findings.append(Finding(language_sources[0].name, 0, 0, "error", "files", exc.message))
        groups += language_groups
        programs += [(target.name, [f.name for f in group]) for group in language_groups]
        for group in language_groups:
            entry = entry_of([f.name for f in group]) if entry_of is not None and dialect.entry_routines else None
            findings.extend(_check_group(dialect, group, CheckOptions(arm=arm, entry=entry)))
    order = {name: i for i, name in enumerate(f.name for f in sources)}
    findings.sort(key=lambda f: (order.get(f.file, len(order)), f.line, f.column))
    counts = {severity: sum(f.severity == severity for f in findings) for severity in SEVERITIES}
    refused = counts["error"] + counts["unsupported"]
    code = EXIT_REFUSED if refused else EXIT_FINDINGS if findings else EXIT_CLEAN
    return Checked(sources, groups, findings, counts, code, titles, names, programs)
