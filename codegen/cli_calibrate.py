"""`codegen calibrate handeye`, `tcp` and `conveyor`: the commands of the calibrate group."""

from __future__ import annotations

import click

from codegen.cli_base import UserError, calibrate
from codegen.cli_base import dump as _dump


@calibrate.command("tcp")
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
    type=float,
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
    from pathlib import Path

    from codegen.cell import CellError
    from codegen.robot.tcp import ToolCalibrationError, fit, read_poses, report_lines, write_to_cell

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


@calibrate.command("handeye")
@click.argument("points", type=click.Path(dir_okay=False))
@click.option("--affine", is_flag=True, help="Fit a general affine map instead of rotation + per-axis scale.")
@click.option(
    "--write",
    "cell_path",
    type=click.Path(exists=True, dir_okay=False),
    help="Write the result into this cell file's [cell.camera.handeye] table.",
)
@click.option("--json", "as_json", is_flag=True, help="Machine-readable output.")
def calibrate_handeye(points: str, affine: bool, cell_path: str | None, as_json: bool) -> None:
    """Fit pixel -> robot mm from a 9-point CSV (header u,v,x,y) by least squares (source 001 eq. 2)."""
    from pathlib import Path

    from codegen.handeye import HandEyeError, fit, read_points, write_to_cell

    path = Path(points)
    try:
        data = read_points(path)
        result = fit(data, "affine" if affine else "similarity", str(path))
        if cell_path:
            write_to_cell(Path(cell_path), result, path.name)
    except HandEyeError as exc:
        raise UserError(str(exc)) from None
    report = {
        "points": result.points,
        "model": result.model,
        "pixel_to_mm": [list(row) for row in result.matrix],
        "rotation_deg": result.rotation_deg,
        "scale_mm_per_px": None if result.scale_mm_per_px is None else list(result.scale_mm_per_px),
        "translation_mm": list(result.translation_mm),
        "residuals_mm": [
            {"line": int(row[0]), "u": row[1], "v": row[2], "residual_mm": r}
            for row, r in zip(data, result.residuals_mm, strict=True)
        ],
        "max_residual_mm": result.max_residual_mm,
        "rms_residual_mm": result.rms_residual_mm,
        "written_to": cell_path,
    }
    if as_json:
        _dump(report)
        return
    click.echo(f"{result.points} points, model {result.model}: [x, y] mm = M [u, v, 1]")
    for row in result.matrix:
        click.echo("  [" + ", ".join(f"{v:.9g}" for v in row) + "]")
    if result.rotation_deg is not None:
        sx, sy = result.scale_mm_per_px
        click.echo(
            f"rotation {result.rotation_deg:.4f} deg, scale x {sx:.7f} mm/px, y {sy:.7f} mm/px, "
            f"translation ({result.translation_mm[0]:.4f}, {result.translation_mm[1]:.4f}) mm"
        )
    for r in report["residuals_mm"]:
        click.echo(f"  line {r['line']}: pixel ({r['u']:g}, {r['v']:g}) residual {r['residual_mm']:.4f} mm")
    click.echo(f"max residual {result.max_residual_mm:.4f} mm, rms {result.rms_residual_mm:.4f} mm")
    if cell_path:
        click.echo(f"wrote [cell.camera.handeye] to {cell_path}")


@calibrate.command("conveyor")
@click.argument("touches", type=click.Path(dir_okay=False))
@click.option(
    "--counter-bits",
    type=click.Choice(["16", "24", "32"]),
    default=None,
    help="The encoder counter's width, for its rollover (default: the cell's [conveyor], else 32).",
)
@click.option("--working-length", type=click.FloatRange(min=1.0), help="The belt's working length (mm): the span rule.")
@click.option(
    "--camera-counts", help="L3,L4: the counts when the block passed the camera and when it stood at the origin."
)
@click.option("--force", is_flag=True, help="Accept touches that span less than half the working length (a warning).")
@click.option(
    "--max-residual",
    type=click.FloatRange(min=0.001),
    default=0.5,
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
def calibrate_conveyor(touches, counter_bits, working_length, camera_counts, force, max_residual, cell_path, as_json):
    """Encoder scale, belt frame and camera offset (source 002) from a CSV x,y,z,count[,role] of a cone on
    the belt touched at two or more places (mm, base frame; upstream first) and optionally one point beside
    the belt (role side, at the height of the cone's tip) that fixes the frame's roll."""
    from pathlib import Path

    from codegen.cell import CellError
    from codegen.conveyor import calibrate as cc

    path = Path(touches)
    try:
        cell_bits, cell_length = cc.cell_settings(Path(cell_path) if cell_path else None)
        bits = int(counter_bits) if counter_bits else (cell_bits or 32)
        length = working_length if working_length is not None else cell_length
        camera = None
        if camera_counts is not None:
            try:
                l3, l4 = (int(v) for v in camera_counts.split(","))
            except ValueError:
                raise UserError(f"--camera-counts {camera_counts}: expected two whole counts L3,L4") from None
            camera = (l3, l4)
        result = cc.fit(path, cc.read_touches(path), bits, length, camera, force, max_residual)
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
