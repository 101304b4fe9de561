"""`codegen correct`: the point mode's reference result for one camera reading."""

from __future__ import annotations

import click

from codegen.cli_base import Number, UserError
from codegen.cli_base import dump as _dump
from codegen.cli_base import load as _load
from codegen.kinds.station.point.correct import correct_report, format_report
from codegen.kinds.station.point.reference import NAME, Reading
from codegen.kinds.station.section import section_of


def _parse_mark(value: str) -> tuple[float, float, float]:
    parts = value.split(",")
    if len(parts) != 3:
        raise UserError(f"--mark: expected X,Y,THETA (3 numbers), got {len(parts)} in {value!r}")
    try:
        return tuple(float(p) for p in parts)  # NaN and inf are allowed: the guard must catch them
    except ValueError:
        raise UserError(f"--mark: not numbers: {value!r}") from None


@click.command("correct")
@click.argument("cell", required=False, type=click.Path(dir_okay=False))
@click.option(
    "--station", "station_id", required=True, type=Number(integer=True), help="Station id read by the camera."
)
@click.option("--mark", required=True, help="Mark now: X,Y,THETA (base frame, mm, deg, as the camera reports).")
@click.option("--json", "as_json", is_flag=True, help="Machine-readable output.")
def correct(cell: str | None, station_id: int, mark: str, as_json: bool) -> None:
    """Reference result for one reading: guard outcome and every corrected pose."""

    model = _load(cell)
    x, y, theta = _parse_mark(mark)
    station = section_of(model).station_by_id(station_id)
    if station is not None and station.mode != NAME:
        raise UserError(
            f"{model.source}: station {station_id} ({station.name}) is a {station.mode} station: only point "
            "stations are corrected from one reading (see `codegen verify` for the others)"
        )
    report = correct_report(model, Reading(station_id, x, y, theta))
    if as_json:
        _dump(report)
    else:
        click.echo(format_report(report))
