"""The command line's group, its bad-input error and the helpers every command module shares."""

from __future__ import annotations

import json

import click

from codegen.model.cell import CellError, load_cell

EXIT_BAD_INPUT = 2


class UserError(click.ClickException):
    """A bad input: message to stderr, exit 2, no traceback."""

    exit_code = EXIT_BAD_INPUT


def load(cell_path):
    try:
        cell = load_cell(cell_path)
    except CellError as exc:
        raise UserError(str(exc)) from None
    for warning in cell.warnings:
        click.echo(f"warning: {warning}", err=True)
    return cell


def step_limit_option(help_text: str):
    """--step-limit of the commands that run programs (the interpreter's default)."""
    from codegen.dialects.core.machine import DEFAULT_STEP_LIMIT

    return click.option(
        "--step-limit", default=DEFAULT_STEP_LIMIT, show_default=True, type=click.IntRange(min=1), help=help_text
    )


def dump(data) -> None:
    click.echo(json.dumps(data, indent=2, sort_keys=False))


@click.group()
@click.version_option(package_name="codegen")
def main() -> None:
    """Vision-corrected robot programs: derive, correct, generate, run, verify."""


@main.group()
def calibrate() -> None:
    """Calibration computations (each kind's: camera, tool, belt)."""
