"""Command line: thin wrappers that parse options, call one function and print."""

from __future__ import annotations

import json
import sys

import click

from codegen.cell import CellError, load_cell

EXIT_BAD_INPUT = 2


class UserError(click.ClickException):
    """A bad input: message to stderr, exit 2, no traceback."""

    exit_code = EXIT_BAD_INPUT


def _load(cell_path):
    try:
        cell = load_cell(cell_path)
    except CellError as exc:
        raise UserError(str(exc)) from None
    for warning in cell.warnings:
        click.echo(f"warning: {warning}", err=True)
    return cell


def _dump(data) -> None:
    click.echo(json.dumps(data, indent=2, sort_keys=False))


@click.group()
@click.version_option(package_name="codegen")
def main() -> None:
    """Vision-corrected robot programs: derive, correct, generate, run, verify."""


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


def _parse_mark(value: str) -> tuple[float, float, float]:
    parts = value.split(",")
    if len(parts) != 3:
        raise UserError(f"--mark: expected X,Y,THETA (3 numbers), got {len(parts)} in {value!r}")
    try:
        return tuple(float(p) for p in parts)  # NaN and inf are allowed: the guard must catch them
    except ValueError:
        raise UserError(f"--mark: not numbers: {value!r}") from None


@main.command()
@click.argument("cell", required=False, type=click.Path(dir_okay=False))
@click.option("--station", "station_id", required=True, type=int, help="Station id read by the camera.")
@click.option("--mark", required=True, help="Mark now: X,Y,THETA (base frame, mm, deg, as the camera reports).")
@click.option("--json", "as_json", is_flag=True, help="Machine-readable output.")
def correct(cell: str | None, station_id: int, mark: str, as_json: bool) -> None:
    """Reference result for one reading: guard outcome and every corrected pose."""
    from codegen.correct import correct_report, format_report
    from codegen.reference import Reading

    model = _load(cell)
    x, y, theta = _parse_mark(mark)
    report = correct_report(model, Reading(station_id, x, y, theta))
    if as_json:
        _dump(report)
    else:
        click.echo(format_report(report))


@main.command()
@click.argument("cell", required=False, type=click.Path(dir_okay=False))
@click.option("--target", "targets", multiple=True, help="Only this target (repeatable); default: the cell's targets.")
@click.option("--out", "out_dir", default="generated", show_default=True, type=click.Path(file_okay=False))
def generate(cell: str | None, targets: tuple[str, ...], out_dir: str) -> None:
    """Write the programs of every target under OUT/<cell>/<target>/ (all or nothing)."""
    from pathlib import Path

    from codegen.emit import EmitError
    from codegen.generate import GenerateError
    from codegen.generate import generate as run_generate

    model = _load(cell)
    for t in targets:
        if t not in model.targets:
            raise UserError(f"--target {t}: not a target of cell {model.name} ({', '.join(model.targets)})")
    try:
        written = run_generate(model, list(targets) or None, Path(out_dir))
    except (EmitError, GenerateError) as exc:
        raise UserError(f"{model.source}: {exc}") from None
    for path in written:
        click.echo(f"wrote {path}")


@main.command()
@click.argument("cell", required=False, type=click.Path(dir_okay=False))
@click.option("--out", "out_dir", default="generated", show_default=True, type=click.Path(file_okay=False))
def diff(cell: str | None, out_dir: str) -> None:
    """Unified diff of fresh output against OUT; exit 1 when they differ."""
    from pathlib import Path

    from codegen.emit import EmitError
    from codegen.generate import diff as run_diff

    model = _load(cell)
    try:
        text = run_diff(model, Path(out_dir))
    except EmitError as exc:
        raise UserError(f"{model.source}: {exc}") from None
    if text:
        click.echo(text, nl=False)
        sys.exit(1)
