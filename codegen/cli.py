"""Command line: thin wrappers that parse options, call one function and print (`codegen` is `main`)."""

from __future__ import annotations

import sys

import click

from codegen import cli_check, cli_init, cli_plant, cli_run  # noqa: F401  (they register their commands)
from codegen.cli_base import (
    Folder,
    Number,
    UserError,
    calibrate,
    chosen_format,
    diff_cell,
    format_option,
    main,
    step_limit_option,
    write_cell,
)
from codegen.cli_base import dump as _dump
from codegen.cli_base import load as _load
from codegen.cli_plant import is_plant_argument
from codegen.controllers import target_names
from codegen.terminal import own_controls
from codegen.view import command as view_command

main.add_command(view_command.view)

PLANT_OUT_HELP = "A plant: default its codegen.toml's `out`, else generated/ in the plant's folder."
MAX_CASES = 1_000_000  # verify's random readings per station: a million runs each; more is a typing slip
MAX_JOBS = 256  # worker processes: beyond the machine's cores each only costs memory


@main.command()
@click.option("--check", is_flag=True, help="Prove every identity; exit 1 unless each has its expected status.")
@click.option("--json", "as_json", is_flag=True, help="Machine-readable output.")
def derive(check: bool, as_json: bool) -> None:
    """Print the derivation of the correction transform (and prove its identities)."""
    from codegen import derivation  # sympy: only this command imports it

    d = derivation.derive()
    result = {"description": derivation.describe(d)}
    ok = True
    if check:
        ids = derivation.identities(d)
        ok = all(i.as_expected for i in ids)
        result["identities"] = [
            {
                "name": i.name,
                "statement": i.statement,
                "expected": i.expected,
                "status": i.status,
                "as_expected": i.as_expected,
                "detail": i.detail,
            }
            for i in ids
        ]
        result["ok"] = ok
    if as_json:
        _dump(result)
    else:
        click.echo(result["description"])
        if check:
            click.echo("")
            click.echo(f"{'identity':<34}{'expected':<10}{'status':<10}ok")
            for i in result["identities"]:
                click.echo(f"{i['name']:<34}{i['expected']:<10}{i['status']:<10}{'yes' if i['as_expected'] else 'NO'}")
                click.echo(f"    {i['statement']}")
                click.echo(f"    {i['detail']}")
            click.echo("all identities as expected" if ok else "SOME IDENTITIES NOT AS EXPECTED")
    sys.exit(0 if ok else 1)


@main.command()
@click.argument("cell", required=False, type=click.Path())
@click.option("--target", "targets", multiple=True, help="Only this target (repeatable); default: the cell's targets.")
@click.option("--out", "out_dir", default="generated", show_default=True, type=Folder(), help=PLANT_OUT_HELP)
@click.option("--json", "as_json", is_flag=True, help="Report written files and the arm's margins as JSON.")
def generate(cell: str | None, targets: tuple[str, ...], out_dir: str, as_json: bool) -> None:
    """Write the programs of every target under OUT/<cell>/<target>/ (all or nothing).

    CELL may be a plant (a folder of cell files, or its codegen.toml): every cell, one table."""
    from pathlib import Path

    if is_plant_argument(cell):
        return cli_plant.generate_plant(cell, targets, out_dir, as_json)
    model = _load(cell)
    for t in targets:
        if t not in model.targets:
            raise UserError(f"--target {t}: not a target of cell {model.name} ({', '.join(model.targets)})")
    from codegen.robot.expect import home_margins

    written, left_alone, envelopes = write_cell(model, list(targets) or None, Path(out_dir))
    homes = home_margins(model, list(targets) or None)
    if as_json:
        _dump(
            {
                "cell": model.name,
                "written": [str(p) for p in written],
                "left_alone": left_alone,
                "home": [h.as_json() for h in homes],
                "envelope": [e.as_json() for e in envelopes],
            }
        )
        return
    for path in written:
        click.echo(f"wrote {path}")
    for note in left_alone:
        click.echo(f"left alone: {note}")
    for home in homes:
        click.echo(home.text())
    for envelope in envelopes:
        click.echo(envelope.text())


@main.command()
@click.argument("cell", required=False, type=click.Path())
@click.option("--out", "out_dir", default="generated", show_default=True, type=Folder(), help=PLANT_OUT_HELP)
@click.option("--json", "as_json", is_flag=True, help="A plant's table as JSON.")
@click.option(
    "--format",
    "diff_format",
    type=click.Choice(["diff", "markdown"]),
    default="diff",
    show_default=True,
    help="A unified diff, or what the change does per program as Markdown (a pull-request comment; a plant: one "
    "document over its changed cells).",
)
@click.option("--no-verify", is_flag=True, help="Markdown: without verify's verdict of the new programs.")
def diff(cell: str | None, out_dir: str, as_json: bool, diff_format: str, no_verify: bool) -> None:
    """Unified diff of fresh output against OUT; exit 1 when they differ. No CELL: every bundled
    example cell (all the cells whose output is committed under generated/). CELL may be a plant (a folder of
    cell files, or its codegen.toml): every cell's diff, then one table."""
    from pathlib import Path

    from codegen.model.cell import example_cells

    if is_plant_argument(cell):
        if diff_format == "markdown":
            return cli_plant.markdown_diff_plant(cell, out_dir, no_verify)
        return cli_plant.diff_plant(cell, out_dir, as_json)
    paths = [cell] if cell is not None else example_cells()
    if diff_format == "markdown":
        _markdown_diff(paths, Path(out_dir), no_verify)
    text, names = "", []
    for path in paths:
        model = _load(path)
        names.append(model.name)
        text += diff_cell(model, Path(out_dir))
    if as_json:
        _dump({"diff": text, "exit": 1 if text else 0})
    elif text:
        click.echo(text, nl=False)
    else:  # a silent success reads as nothing done; stderr keeps stdout the diff alone
        said = f"{len(names)} cells" if len(names) > 1 else f"cell {names[0]}"
        click.echo(f"no differences: the files in {out_dir} are what codegen generate writes for {said}", err=True)
    sys.exit(1 if text else 0)


def _markdown_diff(paths: list, out_dir, no_verify: bool) -> None:
    """diff --format markdown: every cell's change, the new programs verified; exit 1 when any changed."""
    from codegen.emit import EmitError
    from codegen.reports.markdown import markdown
    from codegen.reports.program_diff import add_verdicts, cell_change
    from codegen.robot.taught import ReachError
    from codegen.verify.engine import verify_cell

    changes = []
    for path in paths:
        model = _load(path)
        try:
            change = cell_change(model, out_dir)
            if not no_verify:
                add_verdicts(change, verify_cell(model))
        except (EmitError, ReachError) as exc:
            raise UserError(f"{model.source}: {exc}") from None
        changes.append(change)
    click.echo(markdown(changes), nl=False)
    sys.exit(1 if any(c.programs for c in changes) else 0)


@main.command()
@click.argument("cell", required=False, type=click.Path())
@click.argument("files", nargs=-1, type=click.Path(exists=True, dir_okay=False))
@click.option(
    "--target",
    "targets",
    multiple=True,
    type=click.Choice(target_names()),
    help="Only this target (repeatable).",
)
@click.option(
    "--cases",
    default=1000,
    show_default=True,
    type=Number(0, MAX_CASES, integer=True),
    help="Random readings per station.",
)
@step_limit_option(
    "A run taking more steps is a runaway: a mismatch; that program's remaining cases are skipped. Default: "
    "200,000, or a kind's own where its runs need more (a long measuring cycle).",
    kinds_own=True,
)
@click.option("--seed", default=0, show_default=True, type=Number(0, integer=True))
@click.option(
    "--jobs",
    default=0,
    show_default=True,
    type=Number(0, MAX_JOBS, integer=True),
    help="Worker processes (0: one per CPU).",
)
@click.option(
    "--scheduler",
    envvar="DASK_SCHEDULER_ADDRESS",
    show_envvar=True,
    metavar="ADDRESS",
    help="Run the cases on the Dask cluster of this scheduler (tcp://host:8786; needs codegen[cluster]); "
    "--jobs is then unused.",
)
@click.option("--json", "as_json", is_flag=True, help="Machine-readable report (the same as --format json).")
@format_option()
@click.option("--html", "html_file", type=click.Path(dir_okay=False), help="Also write the report as a page.")
@click.option("--no-cache", is_flag=True, help="A plant: verify every cell again (no stored result is read).")
@click.option(
    "--cache-dir",
    type=Folder(),
    help="A plant: the folder of stored results (default: $CODEGEN_CACHE_DIR, the plant's `cache`, or "
    ".codegen-cache/ in the plant's folder).",
)
@click.option(
    "--timings",
    "timings_file",
    type=click.Path(dir_okay=False),
    help="A plant: also write how long each cell took to this JSON file (--json holds what was found alone: the same "
    "bytes on any machine or cluster).",
)
def verify(
    cell: str | None,
    files: tuple[str, ...],
    targets: tuple[str, ...],
    cases: int,
    step_limit: int | None,
    seed: int,
    jobs: int,
    scheduler: str | None,
    as_json: bool,
    report_format: str,
    html_file: str | None,
    no_cache: bool,
    cache_dir: str | None,
    timings_file: str | None,
) -> None:
    """Run every program of every kind on its cases and the common scenarios; compare with the reference.

    Without FILES the programs are generated fresh; with FILES the files on disk are verified, each matched to
    the cell's program of its name (a .src finds its .dat among the files or beside it).

    CELL may be a plant (a folder of cell files, or its codegen.toml): every cell's programs, fresh, one table;
    a cell whose inputs are unchanged since a stored result reports "cached" (--no-cache: verify every cell).
    """
    from pathlib import Path

    from codegen.dialects.core.values import RunError
    from codegen.emit import EmitError
    from codegen.plant.executors import ClusterError, executor_for
    from codegen.robot.taught import ReachError
    from codegen.verify.engine import Options, verify_cell
    from codegen.verify.programs import ProgramFilesError

    report_format = chosen_format(report_format, as_json)  # a contradiction is said before any case runs
    if is_plant_argument(cell):
        if files or html_file is not None:
            raise UserError(f"{cell}: a plant is verified from its cells; FILES and --html are for one cell")
        return cli_plant.verify_plant(
            cell,
            targets,
            cases,
            seed,
            step_limit,
            jobs,
            scheduler,
            report_format,
            not no_cache,
            cache_dir,
            timings_file,
        )
    if timings_file is not None:
        raise UserError(f"--timings: for a plant; one cell's report has its times ({cell or 'the demo cell'})")
    if cell is not None and Path(cell).suffix.lower() != ".toml":
        files = (cell, *files)
        cell = None
    model = _load(cell)
    for t in targets:
        if t not in model.targets:
            raise UserError(f"--target {t}: not a target of cell {model.name} ({', '.join(model.targets)})")
    view_command.check_html(html_file)

    def run(progress) -> object:
        with executor_for(scheduler, jobs) as executor:
            replays = html_file is not None
            options = Options(cases, seed, jobs, step_limit, progress, keep_replays=replays, executor=executor)
            return verify_cell(model, [Path(f) for f in files], targets, options)

    try:
        if sys.stderr.isatty():
            with click.progressbar(length=0, label="verifying", file=own_controls(sys.stderr)) as bar:
                report = run(bar.update)
        else:
            report = run(None)
    except ClusterError as exc:
        raise UserError(f"--scheduler: {exc}") from None
    except (ProgramFilesError, ReachError, EmitError) as exc:
        raise UserError(f"{model.source}: {exc}" if not isinstance(exc, ProgramFilesError) else str(exc)) from None
    except RunError as exc:  # a program that cannot be loaded here: its files are a bad input
        raise UserError(str(exc)) from None
    for warning in [*report.warnings, *report.margin_warnings()]:
        click.echo(f"warning: {warning}", err=True)
    if not report.rows:
        raise UserError(f"{model.source}: no program to verify for the targets asked")
    if report_format == "json":
        _dump(report.as_json())
    elif report_format == "text":
        for line in report.lines():
            click.echo(line)
    else:
        from codegen.reports.formats import write
        from codegen.reports.from_verify import verify_result
        from codegen.reports.paths import repository_root

        source = model.source if Path(model.source).is_file() else None
        result = verify_result(report, source, Path("generated"))  # fresh programs: where generate writes them
        click.echo(write(report_format, [result], repository_root()), nl=False)
    if html_file is not None:
        view_command.write_report(model, report, html_file)
    sys.exit(0 if report.ok else 1)


@main.command()
def lsp() -> None:
    """Run the language server over standard input and output, for an editor: check's findings as you type,
    hover, outline, definitions, references, completion, and verify against the cell (docs/editor.md)."""
    from codegen.lsp.server import main as serve

    serve()


def _add_kind_commands() -> None:
    """Each program kind's commands on their group (top level, or `codegen calibrate ...`)."""
    from codegen.protocol import installed_kinds

    groups = {None: main, "calibrate": calibrate}
    for kind in installed_kinds().values():
        for group, command in kind.commands.commands():
            groups[group].add_command(command)


_add_kind_commands()
