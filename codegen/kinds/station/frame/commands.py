"""`codegen calibrate handeye`: the 9-point hand-eye calibration of the frame mode's camera (source 001)."""

from __future__ import annotations

from pathlib import Path

import click

from codegen.cli_base import UserError
from codegen.cli_base import dump as _dump
from codegen.kinds.station.frame.handeye import HandEyeError, fit, read_points, write_to_cell


@click.command("handeye")
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
