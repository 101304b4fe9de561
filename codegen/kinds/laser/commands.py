"""`codegen calibrate tcp`: the TCP from flange poses touching one fixed point (source 003's manual method)."""

from __future__ import annotations

from pathlib import Path

import click

from codegen import protocol
from codegen.cli_base import Number, UserError
from codegen.cli_base import dump as _dump
from codegen.kinds.laser.tcp import ToolCalibrationError, fit, read_poses, report_lines, write_to_cell
from codegen.model.cell import CellError


@click.command("tcp")
@click.argument("poses", type=click.Path(dir_okay=False))
@click.option(
    "--method",
    type=click.Choice(["tcp", "tcp-z", "tcp-zx"]),
    default="tcp",
    show_default=True,
    help="tcp: the TCP from the touches; tcp-z, tcp-zx: also the tool's z (and x) axis from rows with role z, x.",
)
@click.option(
    "--max-uncertainty",
    "max_uncertainty",
    type=Number(0.0, above=True),
    default=0.1,
    show_default=True,
    help="Warn when a TCP coordinate's standard uncertainty is above this (mm).",
)
@click.option(
    "--write",
    "cell_path",
    type=click.Path(exists=True, dir_okay=False),
    help="Set the tcp of this cell file's [cell.tool] table.",
)
@click.option("--json", "as_json", is_flag=True, help="Machine-readable output.")
def calibrate_tcp(poses: str, method: str, max_uncertainty: float, cell_path: str | None, as_json: bool) -> None:
    """The TCP from flange poses (CSV header x,y,z,a,b,c[,role]: mm, deg, base frame) touching one fixed point."""

    path = Path(poses)
    try:
        result = fit(path, read_poses(path), method)
        if cell_path is not None:
            write_to_cell(Path(cell_path), result, path.name)
    except (ToolCalibrationError, CellError) as exc:
        raise UserError(str(exc)) from None
    if as_json:
        _dump(result.as_json())
        return
    for line in report_lines(result, max_uncertainty):
        click.echo(line)
    if cell_path is not None:
        click.echo(f"wrote the tcp into {cell_path} [cell.tool]")


class CommandsPart(protocol.Commands):
    def commands(self) -> list:
        return [("calibrate", calibrate_tcp)]
