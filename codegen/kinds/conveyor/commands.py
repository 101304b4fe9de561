"""`codegen calibrate conveyor`: the encoder's scale, the belt frame and the camera offset (source 002)."""

from __future__ import annotations

from pathlib import Path

import click

from codegen import protocol
from codegen.cli_base import Number, UserError
from codegen.cli_base import dump as _dump
from codegen.kinds.conveyor import calibrate as cc
from codegen.model.cell import CellError

WORKING_LENGTH_MAX_MM = 100_000.0  # what the cell's [conveyor] working_length_mm takes


@click.command("conveyor")
@click.argument("touches", type=click.Path(dir_okay=False))
@click.option(
    "--counter-bits",
    type=click.Choice(["16", "24", "32"]),
    default=None,
    help="The encoder counter's width, for its rollover (default: the cell's [conveyor], else 32).",
)
@click.option(
    "--working-length",
    type=Number(1.0, WORKING_LENGTH_MAX_MM),
    help="The belt's working length (mm): the span rule.",
)
@click.option(
    "--camera-counts",
    type=Number(cc.COUNT_MIN, cc.COUNT_MAX, integer=True, count=2),
    help="L3,L4: the counts when the block passed the camera and when it stood at the origin.",
)
@click.option(
    "--ticks",
    is_flag=True,
    help="Fit the robot's own decoder too (UR): the column ticks, encoder_get_tick_count(0) at each touch, "
    "written as ticks_per_mm (the scale the UR program tracks by).",
)
@click.option("--force", is_flag=True, help="Accept touches that span less than half the working length (a warning).")
@click.option(
    "--max-residual",
    type=Number(0.001, cc.POSITION_LIMIT_MM),
    default=cc.MAX_RESIDUAL_MM,
    show_default=True,
    help="Refuse a touch further from the fitted line (mm).",
)
@click.option(
    "--write",
    "cell_path",
    type=click.Path(exists=True, dir_okay=False),
    help="Put the result into this cell file's [conveyor] table.",
)
@click.option("--json", "as_json", is_flag=True, help="Machine-readable output.")
def calibrate_conveyor(
    touches, counter_bits, working_length, camera_counts, ticks, force, max_residual, cell_path, as_json
):
    """Encoder scale, belt frame and camera offset (source 002) from a CSV x,y,z,count[,role][,ticks] of a cone
    on the belt touched at two or more places (mm, base frame; upstream first) and optionally one point beside
    the belt (role side, at the height of the cone's tip) that fixes the frame's roll; with --ticks the robot's
    own decoder's scale from its tick counts at the same touches."""

    path = Path(touches)
    try:
        cell_bits, cell_length, cell_direction = cc.cell_settings(Path(cell_path) if cell_path else None)
        bits = int(counter_bits) if counter_bits else (cell_bits or 32)
        length = working_length if working_length is not None else cell_length
        touched = cc.read_touches(path)
        result = cc.fit(path, touched, bits, length, camera_counts, force, max_residual, cell_direction, ticks)
        if cell_path is not None:
            cc.write_to_cell(Path(cell_path), result, path.name, length)
    except (cc.ConveyorCalibrationError, CellError) as exc:
        raise UserError(str(exc)) from None
    if as_json:
        _dump(result.as_json())
        return
    for line in cc.report_lines(result, path):
        click.echo(line)
    if cell_path is not None:
        click.echo(f"wrote [conveyor] into {cell_path}")


class CommandsPart(protocol.Commands):
    def commands(self) -> list:
        return [("calibrate", calibrate_conveyor)]
