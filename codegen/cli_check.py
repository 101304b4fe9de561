"""`codegen check`: parse and check programs without running them; every finding of every file in one report."""

from __future__ import annotations

import sys

import click

from codegen.checkfiles import check_files
from codegen.cli_base import UserError, chosen_format, file_target_option, format_option, main
from codegen.cli_base import dump as _dump


@main.command()
@click.argument("files", nargs=-1, required=True, type=click.Path(exists=True))
@file_target_option()
@click.option(
    "--robot",
    "robot",
    default=None,
    help="The arm (a catalogue model): speeds the program states are checked against its limits.",
)
@click.option(
    "--entry",
    "entry",
    default=None,
    help="The routine the program starts at instead of its main (RAPID: as after PP to Routine; a module loaded "
    "into the production task, which has the main).",
)
@click.option("--json", "as_json", is_flag=True, help="Machine-readable output (the same as --format json).")
@format_option()
def check(
    files: tuple[str, ...],
    target_name: str | None,
    robot: str | None,
    entry: str | None,
    as_json: bool,
    report_format: str,
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
        if target_name is not None or robot is not None or entry is not None:
            raise UserError(f"{files[0]}: a plant's programs are checked for each cell's targets, arms and entries")
        return check_plant(files[0], None, report_format)
    from codegen.controllers import get_target
    from codegen.dialects import get_dialect

    arm = None
    if robot is not None:
        from codegen.robot.arms import catalogue, find_arm

        arm = find_arm(robot)
        if arm is None:
            raise UserError(f"--robot {robot!r}: not in the catalogue; it has: {', '.join(catalogue())}")
    result = check_files(files, target_name, arm, robot, None if entry is None else lambda _names: entry)
    if entry is not None and not any(get_dialect(get_target(t).dialect).entry_routines for t in result.names):
        raise UserError(f"--entry {entry}: a {', '.join(result.names)} program starts only at its own entry")
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

    from codegen.model.tables import SCHEMA_MARKS, reference_text, schema_text
    from codegen.writefile import WriteRefused, write_own

    text = reference_text() if as_markdown else schema_text()
    if out_file is None:
        click.echo(text, nl=False)
        return
    try:
        write_own(Path(out_file), text, SCHEMA_MARKS)
    except WriteRefused as exc:
        raise UserError(str(exc)) from None
    except OSError as exc:
        raise UserError(f"{out_file}: cannot write: {exc.strerror or exc}; nothing was written") from None
