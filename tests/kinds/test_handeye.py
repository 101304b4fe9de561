"""9-point hand-eye calibration: the fit, its residuals, degenerate sets, writing into a cell."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest
from click.testing import CliRunner

from codegen.cli import main
from codegen.kinds.station.frame.handeye import HandEyeError, fit, read_points
from codegen.kinds.station.section import section_of
from codegen.model.cell import CellError, load_cell

EXAMPLES = Path(__file__).resolve().parents[2] / "codegen" / "examples"


def grid_csv(tmp_path: Path, theta_deg=-2.0, sx=0.02, sy=0.018, tx=5.0, ty=-3.0, points=None) -> Path:
    """Points made by the test's own statement of the model [x y] = R(theta) diag(sx, sy) [u v] + t."""
    th = math.radians(theta_deg)
    rows = ["u,v,x,y"]
    for u, v in points or [(u, v) for v in (100, 500, 900) for u in (150, 600, 1050)]:
        x = math.cos(th) * sx * u - math.sin(th) * sy * v + tx
        y = math.sin(th) * sx * u + math.cos(th) * sy * v + ty
        rows.append(f"{u},{v},{x!r},{y!r}")
    path = tmp_path / "points.csv"
    path.write_text("\n".join(rows) + "\n")
    return path


def test_fit_recovers_the_model(tmp_path):
    result = fit(read_points(grid_csv(tmp_path)))
    assert result.rotation_deg == pytest.approx(-2.0, abs=1e-9)
    assert result.scale_mm_per_px == pytest.approx((0.02, 0.018), abs=1e-12)
    assert result.translation_mm == pytest.approx((5.0, -3.0), abs=1e-9)
    assert result.max_residual_mm < 1e-9


def test_mirrored_camera_has_a_negative_scale(tmp_path):
    result = fit(read_points(grid_csv(tmp_path, theta_deg=10.0, sy=-0.017)))
    assert result.scale_mm_per_px[1] == pytest.approx(-0.017, abs=1e-12)
    assert result.rotation_deg == pytest.approx(10.0, abs=1e-9)


def test_bundled_points_fit_with_small_residuals():
    result = fit(read_points(EXAMPLES / "thermometer_bench_points.csv"))
    assert result.points == 9
    assert 0.0 < result.max_residual_mm < 0.01  # the file carries about 0.002 mm of noise
    assert result.rotation_deg == pytest.approx(1.5, abs=0.05)


def test_affine_model_fits_shear(tmp_path):
    path = tmp_path / "shear.csv"
    rows = ["u,v,x,y"] + [
        f"{u},{v},{0.02 * u + 0.005 * v + 1},{0.018 * v - 2}" for u in (0, 400, 800) for v in (0, 300, 600)
    ]
    path.write_text("\n".join(rows) + "\n")
    assert fit(read_points(path), "affine").max_residual_mm < 1e-9
    assert fit(read_points(path), "similarity").max_residual_mm > 0.1


@pytest.mark.parametrize(
    ("points", "message"),
    [
        ([(0, 0), (100, 0)], "2 distinct points"),
        ([(0, 0), (100, 0), (200, 0), (300, 0)], "pixel points are collinear"),
        ([(0, 0), (100, 0), (0, 100), (0, 0)], "duplicate pixel point (0, 0), also line 2"),
    ],
)
def test_degenerate_sets_are_refused(tmp_path, points, message):
    with pytest.raises(HandEyeError, match=message.replace("(", r"\(").replace(")", r"\)")):
        fit(read_points(grid_csv(tmp_path, points=points)), source="p.csv")


def test_collinear_robot_points_are_refused(tmp_path):
    path = tmp_path / "p.csv"
    path.write_text("u,v,x,y\n0,0,0,0\n100,0,1,0\n0,100,2,0\n")
    with pytest.raises(HandEyeError, match="robot points are collinear"):
        fit(read_points(path), source="p.csv")


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("x,y,u,v\n", "p.csv:1: header must be u,v,x,y"),
        ("u,v,x,y\n1,2,3\n", "p.csv:2: expected 4 values"),
        ("u,v,x,y\n1,2,3,4\n1,b,3,4\n", "p.csv:3: not a number"),
        ("u,v,x,y\n1,2,nan,4\n", "p.csv:2: not a number"),  # nan, inf and 1_0 too: codegen.csvfile
    ],
)
def test_csv_errors_name_the_line(tmp_path, text, message):
    path = tmp_path / "p.csv"
    path.write_text(text)
    with pytest.raises(HandEyeError) as info:
        read_points(path)
    assert str(info.value).endswith(message) or message in str(info.value)


def test_cli_writes_into_the_cell(tmp_path):
    cell = tmp_path / "bench.toml"
    cell.write_text((EXAMPLES / "thermometer_bench.toml").read_text())
    points = grid_csv(tmp_path)
    result = CliRunner().invoke(main, ["calibrate", "handeye", str(points), "--write", str(cell), "--json"])
    assert result.exit_code == 0, result.output
    data = json.loads(result.output)
    assert len(data["residuals_mm"]) == 9 and data["max_residual_mm"] < 1e-9
    loaded = load_cell(cell)
    assert section_of(loaded).handeye[0][2] == pytest.approx(5.0)
    assert section_of(loaded).angle_sign == 1  # this grid's map does not mirror: the bench's -1 is replaced
    assert cell.read_text().count("[cell.camera.handeye]") == 1
    assert "[[station]]" in cell.read_text() and 'name = "tray"' in cell.read_text()


def test_cli_degenerate_exits_2(tmp_path):
    points = grid_csv(tmp_path, points=[(0, 0), (10, 10)])
    result = CliRunner().invoke(main, ["calibrate", "handeye", str(points)])
    assert result.exit_code == 2 and "at least 3" in result.output


def test_write_sets_the_angle_sign_the_image_imposes(tmp_path):
    """The bench's points give a mirrored map (negative determinant): --write sets angle_sign = -1
    even where the cell said +1, and a cell whose sign contradicts its map does not load."""
    text = (EXAMPLES / "thermometer_bench.toml").read_text()
    wrong = text.replace("angle_sign = -1 ", "angle_sign = 1 ", 1)
    assert wrong != text
    cell = tmp_path / "bench.toml"
    cell.write_text(wrong)
    with pytest.raises(CellError, match=r"cell\.camera\.angle_sign: .*negative.*must be -1"):
        load_cell(cell)
    points = EXAMPLES / "thermometer_bench_points.csv"
    result = CliRunner().invoke(main, ["calibrate", "handeye", str(points), "--write", str(cell)])
    assert result.exit_code == 0, result.output
    assert section_of(load_cell(cell)).angle_sign == -1


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (
            "u,v,x,y\n0,0,0,0\n1e-9,0,10,0\n0,1e-9,0,10\n",
            "p.csv: the pixel points lie within 3.33e-10 px of a line (degenerate: at least 1 px across",
        ),
        (
            "u,v,x,y\n0,0,0,0\n100,0,1e-6,0\n0,100,0,1e-6\n",
            "p.csv: the robot points lie within 3.33e-07 mm of a line (degenerate: at least 0.1 mm across",
        ),
    ],
)
def test_points_too_close_together_are_refused_as_degenerate(tmp_path, text, message):
    """Pixel points 1e-9 px apart gave a scale of 1e10 mm/px, accepted. (0,0), (a,0), (0,a): the centred set's
    covariance has eigenvalues a^2 and a^2/3 (sums of squares), so the RMS distance from the best line is a/3."""
    path = tmp_path / "p.csv"
    path.write_text(text)
    with pytest.raises(HandEyeError) as info:
        fit(read_points(path), source="p.csv")
    assert message in str(info.value)
