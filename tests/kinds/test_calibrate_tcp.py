"""`codegen calibrate tcp`: the TCP from touches of one point, its uncertainty, degenerate sets, --write."""

from __future__ import annotations

import json

import numpy as np
import pytest
from click.testing import CliRunner

from codegen.cli import main
from codegen.model.cell import DEMO_CELL, load_cell
from codegen.poses import rotmat_from_zyx_deg, xyzabc_from_matrix
from codegen.render import render

TCP = np.array([12.5, -4.0, 186.0])  # the tool tip in the flange frame, mm
POINT = np.array([650.0, 120.0, 80.0])  # the fixed point in the base frame, mm
DOWN = rotmat_from_zyx_deg(0.0, 0.0, 180.0)  # flange pointing down


def touch(abc_tilt, noise=0.0, rng=None, tcp=TCP):
    """The flange pose (x, y, z, a, b, c) with the tool tip on POINT, the flange tilted by abc from down."""
    rotation = rotmat_from_zyx_deg(*abc_tilt) @ DOWN
    pose = np.eye(4)
    pose[:3, :3] = rotation
    pose[:3, 3] = POINT - rotation @ tcp
    if rng is not None:
        pose[:3, 3] += rng.normal(0.0, noise, 3)
    return xyzabc_from_matrix(pose)


def write_csv(tmp_path, rows, name="poses.csv", roles=None):
    header = "x,y,z,a,b,c" + (",role" if roles else "")
    lines = [header]
    for i, row in enumerate(rows):
        text = ",".join(f"{v:.6f}" for v in row)
        lines.append(text + (f",{roles[i]}" if roles else ""))
    path = tmp_path / name
    path.write_text("\n".join(lines) + "\n")
    return path


def calibrate(*args):
    return CliRunner().invoke(main, ["calibrate", "tcp", *map(str, args)])


def tilts(degrees: float):
    """Six orientations within about `degrees` of each other (about z, y, x and between)."""
    d = degrees
    return [(0, 0, 0), (d, 0, 0), (0, d, 0), (0, 0, d), (0, -d, d), (-d, d / 2, -d)]


def test_recovers_a_known_tcp_within_its_stated_uncertainty(tmp_path):
    rng = np.random.default_rng(5)
    rows = [touch(t, 0.05, rng) for t in tilts(40.0)]
    data = json.loads(calibrate(write_csv(tmp_path, rows), "--json").output)
    error = np.abs(np.array(data["tcp"]) - TCP)
    assert np.all(error <= 3.0 * np.array(data["uncertainty_mm"])), (error, data["uncertainty_mm"])
    assert np.allclose(data["point"], POINT, atol=0.2)
    assert 0 < data["mean_mm"] <= data["max_mm"] < 0.3 and len(data["residuals_mm"]) == 6
    assert data["orientation"] is None and data["orientation_spread_deg"] > 40


def test_a_narrow_pose_set_shows_in_the_uncertainty_not_in_the_residual(tmp_path):
    """The same touch noise: 5 deg of tilt gives about the same residual as 45 deg, a far worse TCP."""
    rng = np.random.default_rng(1)
    wide = json.loads(calibrate(write_csv(tmp_path, [touch(t, 0.05, rng) for t in tilts(45)]), "--json").output)
    rng = np.random.default_rng(1)
    narrow_csv = write_csv(tmp_path, [touch(t, 0.05, rng) for t in tilts(5)], "narrow.csv")
    narrow = json.loads(calibrate(narrow_csv, "--json").output)
    assert narrow["max_mm"] < 3 * wide["max_mm"]
    assert max(narrow["uncertainty_mm"]) > 5 * max(wide["uncertainty_mm"])
    text = calibrate(narrow_csv).output
    assert "warning: an uncertainty is above 0.1 mm" in text and "smallest singular value" in text


@pytest.mark.parametrize(
    ("rows", "message"),
    [
        ([touch(t) for t in [(0, 0, 0), (30, 0, 0), (60, 0, 0), (90, 0, 0)]], "their rotations are all about one axis"),
        ([touch((0, 0, 0)), touch((90, 30, 0))], "2 touches of the point; at least 3"),
        ([touch((0, 0, 0)), touch((90, 30, 0)), touch((0, 0, 0)), touch((0, 0, 30))], "poses.csv:4: the same pose as"),
    ],
)
def test_degenerate_sets_are_refused(tmp_path, rows, message):
    result = calibrate(write_csv(tmp_path, rows))
    assert result.exit_code == 2 and message in result.output and "Traceback" not in result.output


def test_bad_rows_name_the_line(tmp_path):
    path = tmp_path / "bad.csv"
    path.write_text("x,y,z,a,b,c\n1,2,3,4,5,6\n1,2,3,4,five,6\n")
    result = calibrate(path)
    assert result.exit_code == 2 and "bad.csv:3: x..c must be numbers" in result.output


def test_the_tool_axes_from_the_z_and_x_rows(tmp_path):
    tool = rotmat_from_zyx_deg(0.0, 20.0, 0.0)  # the tool's axes in the flange frame: z tilted 20 deg
    rows = [touch(t) for t in tilts(40)]
    last = rotmat_from_zyx_deg(*tilts(40)[-1]) @ DOWN
    for axis in (2, 0):  # from the point, the TCP moved 30 mm along the tool's +Z, then +X
        pose = np.eye(4)
        pose[:3, :3] = last
        pose[:3, 3] = POINT + 30.0 * (last @ tool[:, axis]) - last @ TCP
        rows.append(xyzabc_from_matrix(pose))
    path = write_csv(tmp_path, rows, roles=["point"] * 6 + ["z", "x"])
    data = json.loads(calibrate(path, "--method", "tcp-zx", "--json").output)
    assert np.allclose(data["orientation"], [0.0, 20.0, 0.0], atol=1e-6)
    missing = calibrate(write_csv(tmp_path, rows[:6], "no_z.csv"), "--method", "tcp-z")
    assert missing.exit_code == 2 and "needs a row with role z" in missing.output


def test_write_sets_the_cell_tool_and_the_programs_carry_it(tmp_path):
    cell_path = tmp_path / "cell.toml"
    cell_path.write_text(DEMO_CELL.read_text())
    rows = [touch(t, tcp=np.array([0.0, 0.0, 200.0])) for t in tilts(40)]  # a reachable tool for the demo
    result = calibrate(write_csv(tmp_path, rows), "--write", cell_path)
    assert result.exit_code == 0, result.output
    cell = load_cell(cell_path)
    assert np.allclose(cell.robot.tool.tcp[:3], [0.0, 0.0, 200.0], atol=1e-4)
    assert "# `codegen calibrate tcp` from poses.csv" in cell_path.read_text()
    assert "set_tcp(p[0.0000000, 0.0000000, 0.2000000," in render(cell, ["ur"])[0].text
    far = [touch(t, tcp=np.array([0.0, 0.0, 700.0])) for t in tilts(40)]  # a tool the stations cannot take
    refused = calibrate(write_csv(tmp_path, far, "far.csv"), "--write", cell_path)
    assert refused.exit_code == 2 and "with this tool the cell would not generate: station" in refused.output
    assert load_cell(cell_path).robot.tool.tcp[2] == pytest.approx(200.0, abs=1e-4)  # left as it was


def test_the_bundled_touches_give_the_demo_gripper():
    """codegen/examples/agv_gripper_touches.csv: six touches made for the demo's 200 mm gripper (flange
    poses computed for TCP [0, 0, 200] on a point at [700, -150, 120], 35 deg apart, Gaussian noise of
    0.02 mm on each position, numpy seed 2026, rounded to 0.001 mm / deg)."""
    from codegen.model.cell import EXAMPLES_DIR

    data = json.loads(calibrate(EXAMPLES_DIR / "agv_gripper_touches.csv", "--json").output)
    assert np.all(np.abs(np.array(data["tcp"]) - [0.0, 0.0, 200.0]) <= 3 * np.array(data["uncertainty_mm"]))
    assert max(data["uncertainty_mm"]) < 0.05 and data["max_mm"] < 0.1


def test_the_bundled_four_touches_give_the_laser_cells_bent_pin():
    """codegen/examples/laser_pin_touches.csv: four touches of the laser cell's pin as bent in its verify
    (TCP [1.2, -0.8, 180.7]) on the point [650, -150, 250], tilted 40 deg about z, 30 about y and 30 about
    z and x from down, Gaussian noise of 0.02 mm on each position (numpy seed 2027), rounded to 0.001: the
    least number of touches the method takes beyond its minimum, within 3 of its standard uncertainties."""
    from codegen.model.cell import EXAMPLES_DIR

    data = json.loads(calibrate(EXAMPLES_DIR / "laser_pin_touches.csv", "--json").output)
    assert len(data["residuals_mm"]) == 4
    assert np.all(np.abs(np.array(data["tcp"]) - [1.2, -0.8, 180.7]) <= 3 * np.array(data["uncertainty_mm"]))
    assert max(data["uncertainty_mm"]) < 0.05
