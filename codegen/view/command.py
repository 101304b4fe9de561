"""`codegen view` and the page of `codegen verify --html`: thin, as the rest of the command line."""

from __future__ import annotations

from pathlib import Path

import click

from codegen.cli_base import FOLDER_REFUSED, UserError
from codegen.cli_base import load as load_cell
from codegen.dialects.core.values import RunError
from codegen.emit import EmitError
from codegen.render import cell_dir
from codegen.robot.taught import ReachError
from codegen.view.page import cell_page, check_out, write_page
from codegen.view.report import report_page
from codegen.writefile import WriteRefused


def _write(path: Path, html: str) -> None:
    try:
        write_page(path, html)
    except WriteRefused as exc:
        raise UserError(str(exc)) from None
    except OSError as exc:
        error = UserError if exc.errno in FOLDER_REFUSED else click.ClickException  # the user's to fix: exit 2
        raise error(f"{path}: cannot write ({exc.strerror or exc}); nothing was written") from None


@click.command()
@click.argument("cell", required=False, type=click.Path(dir_okay=False))
@click.option("--target", "targets", multiple=True, help="Only this target (repeatable); default: the cell's targets.")
@click.option("--out", "out_file", type=click.Path(dir_okay=False), help="The page to write (default: <cell>.html).")
def view(cell: str | None, targets: tuple[str, ...], out_file: str | None) -> None:
    """Write one self-contained HTML page of the cell in 3D: each target's arm, the cell's objects and the
    interpreter's nominal run of each program, animated (it opens from disk, with no network)."""
    model = load_cell(cell)
    for t in targets:
        if t not in model.targets:
            raise UserError(f"--target {t}: not a target of cell {model.name} ({', '.join(model.targets)})")
    path = Path(out_file or f"{cell_dir(model)}.html")  # the name as generate makes its folder
    check_html(str(path))  # before the work: a file codegen did not write is left alone
    try:
        html = cell_page(model, list(targets) or list(model.targets))
    except (ReachError, EmitError) as exc:
        raise UserError(f"{model.source}: {exc}") from None
    except RunError as exc:
        raise click.ClickException(str(exc)) from None
    _write(path, html)
    click.echo(f"wrote {path} ({len(html.encode()) / 1e6:.1f} MB)")


def check_html(out_file: str | None) -> None:
    """verify --html: the page's file checked before verify runs (a file codegen did not write is left alone)."""
    if out_file is not None:
        try:
            check_out(Path(out_file))
        except WriteRefused as exc:
            raise UserError(str(exc)) from None


def write_report(model, report, out_file: str) -> None:
    """verify --html: the report's page (its rows kept their replays)."""
    path = Path(out_file)
    html = report_page(model, report)
    _write(path, html)
    click.echo(f"wrote {path} ({len(html.encode()) / 1e6:.1f} MB)", err=True)
