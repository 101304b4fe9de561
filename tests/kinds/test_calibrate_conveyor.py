"""`codegen calibrate conveyor` against a simulated belt (tests/support/belt_sim.py) of known scale, frame, counter."""

import json
import math
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from support import belt_sim

from codegen.cli import main
from codegen.kinds.conveyor.calibrate import unwrap
from codegen.model.cell import load_cell

REPO = Path(__file__).resolve().parents[2]
EXAMPLE = REPO / "codegen" / "examples" / "conveyor_touches.csv"


def run(*args):
    return CliRunner().invoke(main, ["calibrate", "conveyor", *map(str, args)])


def fit_json(path, *extra):
    result = run(path, "--counter-bits", 16, "--working-length", 1500, "--json", *extra)
    assert result.exit_code == 0, result.output
    return json.loads(result.stdout)


def test_the_bundled_touches_come_from_the_simulated_belt():
    assert EXAMPLE.read_text() == belt_sim.csv_text(belt_sim.touches(), ticks=True)


def test_the_robots_own_ticks_give_its_scale_within_the_uncertainty_it_reports():
    """Another encoder on the robot's inputs, counting up (the PLC's counter runs down), rolling over its 16-bit
    filtered count during the touches: the fit unwraps it, signs it and says that the two scales differ."""
    got = fit_json(EXAMPLE, "--ticks")
    sigma = got["ticks_per_mm_uncertainty"]
    assert got["ticks_per_mm"] > 0 and abs(got["ticks_per_mm"] - belt_sim.TRUE_TICKS) <= 3 * sigma, got
    assert sigma < 1e-3 and max(got["ticks_residuals_mm"]) < 0.2
    assert got["ticks_per_count"] == pytest.approx(belt_sim.TRUE_TICKS / belt_sim.TRUE_E, rel=1e-3)
    assert any("count at different scales" in w for w in got["warnings"])
    plain = fit_json(EXAMPLE)  # without --ticks the column is read and left alone
    assert plain["ticks_per_mm"] is None and plain["counts_per_mm"] == got["counts_per_mm"]


def test_ticks_that_count_the_plcs_edges_are_no_mismatch(tmp_path):
    header, *rows = EXAMPLE.read_text().splitlines()
    same = [",".join([*r.split(",")[:5], str(int(r.split(",")[3]) % 2**16)]) for r in rows]  # the PLC's own counts
    path = tmp_path / "same.csv"
    path.write_text("\n".join([header, *same]) + "\n")
    got = fit_json(path, "--ticks")
    assert got["ticks_per_count"] == pytest.approx(1.0) and got["ticks_per_mm"] == pytest.approx(got["counts_per_mm"])
    assert not any("different scales" in w for w in got["warnings"])


def test_ticks_are_written_into_the_cell_and_kept_by_a_calibration_without_them(tmp_path):
    cell = tmp_path / "cell.toml"
    cell.write_text((REPO / "codegen" / "examples" / "agv_machine_tending.toml").read_text())
    result = run(EXAMPLE, "--counter-bits", 16, "--working-length", 1500, "--ticks", "--write", cell)
    assert result.exit_code == 0, result.output
    assert "robot's ticks T = 5.09" in result.output
    assert load_cell(cell).sections["conveyor"].ticks_per_mm == pytest.approx(belt_sim.TRUE_TICKS, abs=2e-3)
    assert run(EXAMPLE, "--write", cell).exit_code == 0
    assert load_cell(cell).sections["conveyor"].ticks_per_mm == pytest.approx(belt_sim.TRUE_TICKS, abs=2e-3)


def _with_ticks(tmp_path, ticks: list[str]):
    header, *rows = EXAMPLE.read_text().splitlines()
    out = [header] + [",".join([*r.split(",")[:5], t]) for r, t in zip(rows, ticks, strict=True)]
    path = tmp_path / "t.csv"
    path.write_text("\n".join(out) + "\n")
    return path


@pytest.mark.parametrize(
    ("ticks", "says"),
    [
        (["61000", "62783", "-3", "557", ""], "t.csv:4: ticks must be the robot's encoder_get_tick_count(0)"),
        (["61000", "62783", "65536", "557", ""], "t.csv:4: ticks must be the robot's"),
        (["61000", "62783", "645.5", "557", ""], "t.csv:4: ticks must be the robot's"),
        (["61000", "", "64565", "557", ""], "t.csv:3: ticks must be the robot's"),
        (["61000", "61000", "64565", "557", ""], "t.csv:3: the same tick count as line 2: the robot's encoder did not"),
        # a tick count latched 20 ticks (about 4 mm of travel) off the PLC's count at the third touch
        (["61000", "62783", "64585", "557", ""], "t.csv:4: the robot's tick count and the PLC's count disagree by"),
    ],
)
def test_bad_tick_data_is_refused_naming_its_line(tmp_path, ticks, says):
    result = run(_with_ticks(tmp_path, ticks), "--counter-bits", 16, "--working-length", 1500, "--ticks")
    assert result.exit_code == 2 and says in result.output and "Traceback" not in result.output, result.output


def test_ticks_asked_for_without_a_ticks_column_are_refused(tmp_path):
    path = tmp_path / "t.csv"
    path.write_text(belt_sim.csv_text(belt_sim.touches()))
    result = run(path, "--counter-bits", 16, "--working-length", 1500, "--ticks")
    says = "t.csv:2: --ticks needs the robot's tick count at every belt touch"
    assert result.exit_code == 2 and says in result.output


def test_a_known_belt_is_recovered_within_the_uncertainty_it_reports():
    """Counting down through the 16-bit rollover, tilted 2 deg about its axis (the side point fixes it)."""
    l3, l4 = belt_sim.camera_counts()
    got = fit_json(EXAMPLE, "--camera-counts", f"{l3},{l4}")
    sigma = got["counts_per_mm_uncertainty"]
    assert got["counts_per_mm"] < 0 and abs(got["counts_per_mm"] - belt_sim.TRUE_E) <= 3 * sigma
    truth = belt_sim.belt2base()
    frame = np.array(got["frame"])
    assert np.degrees(np.arccos(np.clip(frame[:3, 1] @ truth[:3, 1], -1, 1))) < 0.01  # +Y, the travel
    assert np.degrees(np.arccos(np.clip(frame[:3, 2] @ truth[:3, 2], -1, 1))) < 0.1  # the roll
    assert np.linalg.norm(frame[:3, 3] - truth[:3, 3]) < 0.2  # the origin at the downstream touch
    camera_sigma = belt_sim.CAMERA_UPSTREAM_MM * 3 * sigma / abs(belt_sim.TRUE_E) + 0.1  # and one count
    assert abs(got["camera_offset_mm"] - belt_sim.CAMERA_UPSTREAM_MM) <= camera_sigma
    assert set(got) >= {"counts_per_mm", "direction", "origin", "frame", "residuals_mm", "camera_offset_mm"}
    assert len(got["residuals_mm"]) == 4 and max(got["residuals_mm"]) < 0.2


def test_without_a_side_point_the_roll_comes_from_the_base_z(tmp_path):
    path = tmp_path / "t.csv"
    path.write_text("\n".join(EXAMPLE.read_text().splitlines()[:-1]) + "\n")  # no side point
    got = fit_json(path)
    z = np.array(got["frame"])[:3, 2]
    assert got["roll_from"] == "the robot base's z" and abs(z @ np.array(got["direction"])) < 1e-12
    assert np.degrees(np.arccos(z[2] / np.linalg.norm(z))) < 0.01  # the base's z, square to the belt


def test_unwrapping_the_counter():
    assert unwrap([65_530, 4, 60], 16).tolist() == [0, 10, 66]
    assert unwrap([10, 65_530], 16).tolist() == [0, -16]  # counting down through 0
    assert unwrap([2**32 - 1, 5], 32).tolist() == [0, 6]


def test_a_wrong_counter_width_is_caught_by_the_fit():
    """Read as 32 bit, the 16-bit rollover jumps by 65,536 counts: no straight line fits the touches."""
    result = run(EXAMPLE, "--counter-bits", 32, "--working-length", 1500)
    assert result.exit_code == 2 and "from the fitted belt line" in result.output


@pytest.mark.parametrize(
    ("rows", "options", "says"),
    [
        (["1,2,3,100,belt"], (), "1 belt touches; at least 2"),
        (["0,0,0,100,belt", "500,0,0,100,belt"], (), "the same count as line 2: the belt did not move"),
        (["0,0,0,100,belt", "500,0,0,4100,belt"], ("--working-length", 2000), "span 500.0 mm, less than half"),
        (["0,0,0,100,belt", "500,0,0,4100,belt"], (), "the belt's working length is not known"),
        (["0,0,0,100,belt", "250,3,0,2100,belt", "500,0,0,4100,belt"], ("--working-length", 900), "2.000 mm from"),
        (["0,0,0,100,belt", "500,0,0,4100,belt", "250,2,0,2100,side"], ("--working-length", 900), "side point is"),
        (["0,0,0,abc,belt"], (), "t.csv:2: x, y, z must be numbers and count a whole number"),
        (["0,0,0,1,belt", "0,0,0,5,belt"], ("--force",), "the belt touches lie within 0.000 mm of each other"),
        (["0,0,0,1,sideways"], (), "t.csv:2: role must be belt or side"),
    ],
)
def test_touches_that_cannot_calibrate_are_refused(tmp_path, rows, options, says):
    path = tmp_path / "t.csv"
    path.write_text("x,y,z,count,role\n" + "\n".join(rows) + "\n")
    result = run(path, *options)
    assert result.exit_code == 2 and says in result.output and "Traceback" not in result.output, result.output


def test_a_short_span_passes_with_force_and_says_so(tmp_path):
    path = tmp_path / "t.csv"
    path.write_text("x,y,z,count\n0,0,0,100\n500,0,0,4100\n")
    got = json.loads(run(path, "--working-length", 2000, "--force", "--json").stdout)
    assert got["counts_per_mm"] == pytest.approx(8.0) and any("less than half" in w for w in got["warnings"])
    assert got["counts_per_mm_uncertainty"] is None and any("two touches" in w for w in got["warnings"])


def test_write_puts_the_result_into_the_cell_and_replaces_it_the_next_time(tmp_path):
    cell = tmp_path / "cell.toml"
    cell.write_text((REPO / "codegen" / "examples" / "agv_machine_tending.toml").read_text())
    for _ in range(2):
        result = run(EXAMPLE, "--counter-bits", 16, "--working-length", 1500, "--write", cell)
        assert result.exit_code == 0, result.output
    assert cell.read_text().count("[conveyor]") == 1
    conveyor = load_cell(cell).sections["conveyor"]
    assert conveyor.counter_bits == 16 and conveyor.working_length_mm == 1500
    assert conveyor.counts_per_mm == pytest.approx(belt_sim.TRUE_E, abs=2e-3)
    assert np.allclose(conveyor.frame()[:3, 1], belt_sim.belt2base()[:3, 1], atol=1e-3)
    # the next calibration reads the counter width and the working length from the cell
    assert run(EXAMPLE, "--write", cell).exit_code == 0
    assert math.isclose(load_cell(cell).sections["conveyor"].working_length_mm, 1500)


@pytest.mark.parametrize(
    ("table", "says"),
    [
        ("counter_bits = 20", r"conveyor\.counter_bits: expected one of 16, 24, 32"),
        ("counts_per_mm = 8.0", r"conveyor: counts_per_mm, origin, direction and z_axis come together"),
        (
            "counts_per_mm = 8.0\norigin = [0, 0, 0]\ndirection = [1, 1, 0]\nz_axis = [0, 0, 1]",
            r"conveyor\.direction: must be a unit vector",
        ),
        (
            "counts_per_mm = 8.0\norigin = [0, 0, 0]\ndirection = [1, 0, 0]\nz_axis = [1, 0, 0]",
            r"conveyor\.z_axis: must be at right angles",
        ),
        ("belt_speed = 3", r"conveyor\.belt_speed: unknown key"),
        ("ticks_per_mm = 5.0", r"conveyor\.ticks_per_mm: needs the belt calibrated: counts_per_mm"),
        (
            "counts_per_mm = 8.0\norigin = [0, 0, 0]\ndirection = [0, 1, 0]\nz_axis = [0, 0, 1]\nticks_per_mm = 0.0001",
            r"conveyor\.ticks_per_mm: must be a signed scale of 0\.001 to 1e6 ticks per mm",
        ),
    ],
)
def test_a_bad_conveyor_table_names_its_key(tmp_path, table, says):
    from codegen.model.cell import CellError

    cell = tmp_path / "cell.toml"
    cell.write_text(
        (REPO / "codegen" / "examples" / "agv_machine_tending.toml").read_text() + f"\n[conveyor]\n{table}\n"
    )
    with pytest.raises(CellError, match=says):
        load_cell(cell)


def test_a_recalibration_keeps_the_camera_offset_and_the_next_tables_comments(tmp_path):
    cell = tmp_path / "cell.toml"
    demo = (REPO / "codegen" / "examples" / "agv_machine_tending.toml").read_text()
    cell.write_text(
        "[conveyor]\ncounter_bits = 16\n\n# the stations\n"
        + demo[demo.index("[[station]]") :]
        + demo[: demo.index("[[station]]")]
    )
    l3, l4 = belt_sim.camera_counts()
    assert run(EXAMPLE, "--working-length", 1500, "--camera-counts", f"{l3},{l4}", "--write", cell).exit_code == 0
    assert run(EXAMPLE, "--write", cell).exit_code == 0  # no camera counts this time
    text = cell.read_text()
    assert "# the stations\n[[station]]" in text and text.count("[conveyor]") == 1
    assert load_cell(cell).sections["conveyor"].camera_offset_mm == pytest.approx(belt_sim.CAMERA_UPSTREAM_MM, abs=0.5)


def test_touches_listed_downstream_first_are_named_as_reversed(tmp_path):
    """A belt turned round against the cell's was written without a word."""
    cell = tmp_path / "cell.toml"
    cell.write_text((REPO / "codegen" / "examples" / "agv_machine_tending.toml").read_text())
    assert run(EXAMPLE, "--counter-bits", 16, "--working-length", 1500, "--write", cell).exit_code == 0
    before = cell.read_text()
    header, *rows = EXAMPLE.read_text().splitlines()
    belt, side = [r for r in rows if r.split(",")[4] == "belt"], [r for r in rows if r.split(",")[4] != "belt"]
    reversed_touches = tmp_path / "reversed.csv"
    reversed_touches.write_text("\n".join([header, *belt[::-1], *side]) + "\n")
    result = run(reversed_touches, "--write", cell)
    assert result.exit_code == 2, result.output
    assert "reversed.csv: the touches give a belt running against the cell's direction" in result.stderr
    assert "(reversed): listed downstream first" in result.stderr and "reverse the rows, or --force" in result.stderr
    assert cell.read_text() == before
    forced = run(reversed_touches, "--write", cell, "--force")
    assert forced.exit_code == 0, forced.output
    assert "warning: the touches give a belt running against the cell's direction" in forced.output
    assert run(EXAMPLE, "--write", tmp_path / "cell.toml", "--force").exit_code == 0  # and back again
