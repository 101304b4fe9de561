"""`codegen check`: parse and check programs without running them; every finding of every file in one report."""

from __future__ import annotations

import inspect
import sys
from dataclasses import dataclass

import click

from codegen.cli_base import UserError, chosen_format, file_target_option, format_option, main
from codegen.cli_base import dump as _dump
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
        return dialect.check_files(group, options) if takes_options else dialect.check_files(group)
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


def check_files(files: tuple[str, ...], target_name: str | None, arm=None, robot: str | None = None) -> Checked:
    """Every finding of the files (and folders) given, as `codegen check` reports them; UserError for a file that
    is no program of a language or an arm of another controller."""
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
            findings.extend(_check_group(dialect, group, CheckOptions(arm=arm)))
    order = {name: i for i, name in enumerate(f.name for f in sources)}
    findings.sort(key=lambda f: (order.get(f.file, len(order)), f.line, f.column))
    counts = {severity: sum(f.severity == severity for f in findings) for severity in SEVERITIES}
    refused = counts["error"] + counts["unsupported"]
    code = EXIT_REFUSED if refused else EXIT_FINDINGS if findings else EXIT_CLEAN
    return Checked(sources, groups, findings, counts, code, titles, names, programs)


@main.command()
@click.argument("files", nargs=-1, required=True, type=click.Path(exists=True))
@file_target_option()
@click.option(
    "--robot",
    "robot",
    default=None,
    help="The arm (a catalogue model): speeds the program states are checked against its limits.",
)
@click.option("--json", "as_json", is_flag=True, help="Machine-readable output (the same as --format json).")
@format_option()
def check(
    files: tuple[str, ...], target_name: str | None, robot: str | None, as_json: bool, report_format: str
) -> None:
    """Parse and check programs without running them, like a compiler: every syntax error, unsupported
    construct, undefined name and the field checks of each language (a wait without a timeout, motion before
    the tool is set, speeds over the arm's ...), of all files, with file:line.

    FILES: program files, or folders holding them (the files of one program are checked together). Exit 0
    clean, 1 findings (warnings), 2 a file does not parse or uses what the interpreter does not model. A plant
    (its codegen.toml, or a folder holding it or cell files): each cell's programs in the plant's output folder,
    against each cell's arm, one table."""
    from codegen.cli_plant import check_plant, is_plant_folder

    report_format = chosen_format(report_format, as_json)  # a contradiction is said before anything is read
    if len(files) == 1 and is_plant_folder(files[0]):
        if target_name is not None or robot is not None:
            raise UserError(f"{files[0]}: a plant's programs are checked for each cell's targets and arms")
        if report_format not in ("text", "json"):
            raise UserError(f"{files[0]}: --format {report_format} is for program files; a plant reports its table")
        return check_plant(files[0], None, report_format == "json")
    arm = None
    if robot is not None:
        from codegen.robot.arms import catalogue, find_arm

        arm = find_arm(robot)
        if arm is None:
            raise UserError(f"--robot {robot!r}: not in the catalogue; it has: {', '.join(catalogue())}")
    result = check_files(files, target_name, arm, robot)
    findings, sources, groups, counts, code = (
        result.findings,
        result.sources,
        result.groups,
        result.counts,
        result.code,
    )
    titles, names = result.titles, result.names
    if report_format not in ("text", "json"):
        from codegen.reports.formats import write
        from codegen.reports.from_check import check_result
        from codegen.reports.paths import repository_root

        click.echo(write(report_format, [check_result(result.programs, findings)], repository_root()), nl=False)
        sys.exit(code)
    if report_format == "json":
        _dump(
            {
                "target": names[0] if len(names) == 1 else None,
                "targets": names,
                "files": [f.name for f in sources],
                "programs": [[f.name for f in group] for group in groups],
                "findings": [f.as_json() for f in findings],
                "counts": counts,
                "exit": code,
            }
        )
        sys.exit(code)
    for finding in findings:
        click.echo(finding.text())
    files_text = f"{len(sources)} file{'s' if len(sources) != 1 else ''}"
    if not findings:
        click.echo(
            f"clean: {files_text} of {', '.join(titles)}, {len(groups)} program{'s' if len(groups) != 1 else ''}"
        )
    else:
        shown = ", ".join(
            f"{n} {severity}{'s' if n != 1 and severity != 'unsupported' else ''}"
            for severity, n in counts.items()
            if n
        )
        click.echo(f"{len(findings)} finding{'s' if len(findings) != 1 else ''} in {files_text}: {shown}")
    sys.exit(code)


@main.command()
@click.option("--out", "out_file", type=click.Path(dir_okay=False), help="Write to this file instead of printing.")
@click.option("--markdown", "as_markdown", is_flag=True, help="The cell-file reference as Markdown instead.")
def schema(out_file: str | None, as_markdown: bool) -> None:
    """Print the cell file's JSON Schema (draft 2020-12), or its reference page, from the loader's definition."""
    from pathlib import Path

    from codegen.model.tables import reference_text, schema_text

    text = reference_text() if as_markdown else schema_text()
    if out_file is None:
        click.echo(text, nl=False)
        return
    try:
        Path(out_file).write_text(text, encoding="utf-8")
    except OSError as exc:
        raise UserError(f"{out_file}: cannot write: {exc.strerror or exc}") from None
