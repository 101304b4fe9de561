"""Cell loading: the demo cell, and one test per class of bad input."""

from __future__ import annotations

import math
import re
import subprocess
import sys

import pytest
from support.cells import MINIMAL_CELL

from codegen.kinds.station.section import section_of, stations_of
from codegen.model.cell import CellError, load_cell


def test_demo_cell_loads(demo_cell):
    assert demo_cell.name == "agv_machine_tending"
    assert [s.id for s in stations_of(demo_cell)] == [1, 2, 3, 4, 5, 6, 7]
    assert section_of(demo_cell).angle_sign == -1
    assert section_of(demo_cell).limits.max_shift_mm == 10.0
    # the machines are tended (the finished part out onto the tray, the raw part in); the others are visited
    assert [len(s.poses) for s in stations_of(demo_cell)] == [11] * 5 + [2, 2]
    assert [s.holds_at_start for s in stations_of(demo_cell)] == [False] * 5 + [None, None]
    assert len(demo_cell.sha256) == 64


def test_minimal_cell_keeps_pose_order(write_cell):
    cell = load_cell(write_cell(MINIMAL_CELL))
    assert [p.name for p in stations_of(cell)[0].poses] == ["approach", "chuck"]


def test_a_pose_keeps_its_name_as_written(write_cell):
    """A quoted pose name with a dot in it is one name (TOML's), not a key path."""
    cell = load_cell(write_cell(MINIMAL_CELL.replace("\nchuck = [", '\n"chuck.left" = [')))
    assert [p.name for p in stations_of(cell)[0].poses] == ["approach", "chuck.left"]


def _error(write_cell, text: str) -> str:
    path = write_cell(text)
    with pytest.raises(CellError) as info:
        load_cell(path)
    message = str(info.value)
    assert message.startswith(str(path) + ": "), message
    return message


BAD = {
    "toml_syntax": (
        MINIMAL_CELL.replace('name = "bench"', 'name = "bench'),
        "line 2",
    ),
    "pose_count": (
        MINIMAL_CELL.replace(
            "chuck = [700.0, -100.0, 300.0, 90.0, 0.0, 180.0]", "chuck = [700.0, -100.0, 300.0, 90.0, 0.0]"
        ),
        "station[0].poses.chuck: expected 6 numbers, got 5",
    ),
    "nan": (
        MINIMAL_CELL.replace("mark = [600.0, -250.0, 2.0]", "mark = [nan, -250.0, 2.0]"),
        "station[0].mark[0]: expected a finite number, got nan",
    ),
    "inf": (
        MINIMAL_CELL.replace("vise = [700.0,", "vise = [inf,"),
        "station[1].poses.vise[0]: expected a finite number, got inf",
    ),
    "mode_not_a_string": (
        MINIMAL_CELL.replace('name = "mill_1"', 'name = "mill_1"\nmode = ["point"]'),
        "station[1].mode: expected one of 'point', 'frame' (the station's program kind), got a list of 1",
    ),
    "mode_a_table": (
        MINIMAL_CELL.replace('name = "mill_1"', 'name = "mill_1"\nmode = {kind = "point"}'),
        "station[1].mode: expected one of 'point', 'frame' (the station's program kind), got a table",
    ),
    "string_number": (
        MINIMAL_CELL.replace("max_shift_mm = 10.0", 'max_shift_mm = "10"'),
        "cell.limits.max_shift_mm: expected a number, got the string '10'",
    ),
    "duplicate_id": (
        MINIMAL_CELL.replace("id = 2", "id = 1"),
        "station[1].id: duplicate station id 1",
    ),
    "duplicate_name": (
        MINIMAL_CELL.replace('name = "mill_1"', 'name = "lathe_1"'),
        "station[1].name: duplicate station name 'lathe_1'",
    ),
    "unknown_target": (
        MINIMAL_CELL.replace("targets = [", 'targets = ["fanuc", '),
        "cell.targets[0]: expected one of 'abb', 'dtrans', 'kuka', 'ur' (a controller), got 'fanuc'",
    ),
    "unknown_pose_format": (
        MINIMAL_CELL.replace('pose_format = "xyzabc"', 'pose_format = "euler"'),
        "cell.pose_format: expected one of 'xyzabc', 'ur', 'abb' (how a taught pose is written), got 'euler'",
    ),
    "zero_shift_limit": (
        MINIMAL_CELL.replace("max_shift_mm = 10.0", "max_shift_mm = 0.0"),
        "cell.limits.max_shift_mm: must be in (0, 100000] mm (the largest shift of the mark), got 0",
    ),
    "negative_rotation_limit": (
        MINIMAL_CELL.replace("max_rotation_deg = 10.0", "max_rotation_deg = -1"),
        "cell.limits.max_rotation_deg: must be in (0, 180)",
    ),
    "station_without_poses": (
        MINIMAL_CELL.replace("vise = [700.0, 50.0, 260.0, -90.0, 15.0, 180.0]\n", ""),
        "station[1].poses: expected at least one entry (the taught poses by name",
    ),
    "missing_key": (
        MINIMAL_CELL.replace("angle_sign = -1\n", ""),
        "cell.camera.angle_sign: missing",
    ),
    "bad_angle_sign": (
        MINIMAL_CELL.replace("angle_sign = -1", "angle_sign = 2"),
        "cell.camera.angle_sign: expected one of 1, -1 (the sign the camera's angles turn with: -1 when its image is "
        "mirrored (they turn against the frame's)), got 2",
    ),
    "unknown_key": (
        MINIMAL_CELL.replace("max_shift_mm = 10.0", "max_shift_mm = 10.0\nmax_shfit = 3"),
        "cell.limits.max_shfit: unknown key",
    ),
    "no_stations": (
        MINIMAL_CELL.split("[[station]]")[0],
        "station: expected at least one [[station]] table",
    ),
    "station_id_not_integer": (
        MINIMAL_CELL.replace("id = 2", "id = 2.5"),
        "station[1].id: expected a whole number (no decimal point) in 1..32767, got the number 2.5",
    ),
    "station_id_out_of_range": (
        MINIMAL_CELL.replace("id = 2", "id = 0"),
        "station[1].id: expected a whole number in 1..32767 (the station's id (the barcode the vision PC reads)), got "
        "the number 0",
    ),
    "empty_name": (
        MINIMAL_CELL.replace('name = "mill_1"', 'name = "  "'),
        "station[1].name: expected a non-empty string",
    ),
    "mark_theta_out_of_range": (
        MINIMAL_CELL.replace("mark = [640.0, 210.0, 0.0]", "mark = [640.0, 210.0, 400.0]"),
        "station[1].mark[2]: theta must be within",
    ),
    "boolean_number": (
        MINIMAL_CELL.replace("max_rotation_deg = 10.0", "max_rotation_deg = true"),
        "cell.limits.max_rotation_deg: expected a number, got a boolean",
    ),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_input_is_named(write_cell, case):
    text, expected = BAD[case]
    assert expected in _error(write_cell, text)


def test_missing_file_is_named(tmp_path):
    with pytest.raises(CellError, match="cannot read cell file"):
        load_cell(tmp_path / "nope.toml")


def test_abb_quaternion_normalised_with_warning(write_cell):
    text = (
        MINIMAL_CELL.replace('pose_format = "xyzabc"', 'pose_format = "abb"')
        .replace("[650.0, -100.0, 400.0, 90.0, 0.0, 180.0]", "[650.0, -100.0, 400.0, 0.0, 0.0, 0.0, 2.0]")
        .replace("[700.0, -100.0, 300.0, 90.0, 0.0, 180.0]", "[700.0, -100.0, 300.0, 0.0, 0.0, 0.0, 1.0]")
        .replace("[700.0, 50.0, 260.0, -90.0, 15.0, 180.0]", "[700.0, 50.0, 260.0, 0.5, 0.5, 0.5, 0.5]")
    )
    cell = load_cell(write_cell(text))
    assert stations_of(cell)[0].poses[0].values[3:] == (0.0, 0.0, 0.0, 1.0)
    assert len(cell.warnings) == 1
    assert "station[0].poses.approach: quaternion norm 2 normalised" in cell.warnings[0]


def test_abb_zero_quaternion_rejected(write_cell):
    text = MINIMAL_CELL.replace('pose_format = "xyzabc"', 'pose_format = "abb"').replace(
        "[650.0, -100.0, 400.0, 90.0, 0.0, 180.0]", "[650.0, -100.0, 400.0, 0.0, 0.0, 0.0, 0.0]"
    )
    assert "station[0].poses.approach: quaternion q1..q4 is zero" in _error(write_cell, text)


def test_ur_pose_format_in_metres(write_cell):
    text = (
        MINIMAL_CELL.replace('pose_format = "xyzabc"', 'pose_format = "ur"')
        .replace("[650.0, -100.0, 400.0, 90.0, 0.0, 180.0]", "[0.65, -0.1, 0.4, 0.0, 3.14159, 0.0]")
        .replace("[700.0, -100.0, 300.0, 90.0, 0.0, 180.0]", "[0.7, -0.1, 0.3, 0.0, 3.14159, 0.0]")
        .replace("[700.0, 50.0, 260.0, -90.0, 15.0, 180.0]", "[0.7, 0.05, 0.26, 0.0, 3.14159, 0.0]")
    )
    cell = load_cell(write_cell(text))
    m = stations_of(cell)[0].poses[0].matrix()
    assert math.isclose(m[0, 3], 650.0)


def test_cli_bad_cell_exits_2_without_traceback(write_cell):
    path = write_cell(BAD["pose_count"][0])
    proc = subprocess.run(
        [sys.executable, "-m", "codegen", "correct", str(path), "--station", "1", "--mark", "1,2,3"],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 2
    assert "Traceback" not in proc.stderr
    assert "station[0].poses.chuck: expected 6 numbers, got 5" in proc.stderr


def _one_pose_cell(pose_format: str, pose: str) -> str:
    head = MINIMAL_CELL[: MINIMAL_CELL.index("[[station]]")].replace('"xyzabc"', f'"{pose_format}"')
    return head + f'[[station]]\nid = 1\nname = "a"\nmark = [600.0, -250.0, 2.0]\n[station.poses]\nwork = {pose}\n'


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (MINIMAL_CELL.replace('name = "mill_1"', 'name = "mill_1"\nx = ' + "[" * 999 + "]" * 999), "nested too deeply"),
        (_one_pose_cell("abb", "[700.0, 50.0, 260.0, 1e200, 1e200, 0, 0]"), "quaternion q1..q4 must be within +-10"),
        (_one_pose_cell("xyzabc", "[700, 50, 260, 90, 0, 1e20]"), "orientation values must be within +-360 deg"),
        (_one_pose_cell("ur", "[0.7, 0.05, 0.26, 1e200, 0, 0]"), "orientation values must be within +-6.28319 rad"),
    ],
)
def test_hostile_numbers_and_nesting_are_named_not_raised(write_cell, text, message):
    """Found by a fault probe: each raised a Python error (or generated) instead of naming the key."""
    with pytest.raises(CellError, match=re.escape(message)):
        load_cell(write_cell(text))


def test_marks_and_poses_only_where_float32_meets_verify_tolerance(write_cell):
    """At 100 km a float32 controller corrects 0.008 mm off, beyond verify's 0.005 mm: refused."""
    far = MINIMAL_CELL.replace("mark = [600.0, -250.0, 2.0]", "mark = [100000.0, -100000.0, 0.0]")
    float32 = r"station\[0\]\.mark\[0\]: must be in \[-10000, 10000\] .*, got 100000 \(float32 on the controller\)"
    with pytest.raises(CellError, match=float32):
        load_cell(write_cell(far))
    pose = MINIMAL_CELL.replace("vise = [700.0, 50.0,", "vise = [10700.0, 50.0,")
    with pytest.raises(CellError, match=r"station\[1\]\.poses\.vise: position must be within \+-10000"):
        load_cell(write_cell(pose))


def test_sizes_beyond_what_verify_can_run_are_refused_at_load(write_cell):
    """3,000 stations made UR and dtrans programs too deeply nested to run, 10,000 poses reached the
    step limit: refused with the limit instead of failing later."""
    head = MINIMAL_CELL[: MINIMAL_CELL.index("[[station]]")]
    station = (
        '[[station]]\nid = {i}\nname = "s{i}"\nmark = [600.0, -250.0, 2.0]\n'
        "[station.poses]\nw = [650, -100, 400, 90, 0, 180]\n"
    )
    many = head + "".join(station.format(i=i) for i in range(1, 5002))
    with pytest.raises(CellError, match=r"station: 5001 stations; at most 5000"):
        load_cell(write_cell(many))
    poses = "".join(f"p{i} = [650, -100, 400, 90, 0, 180]\n" for i in range(1001))
    long_station = head + station.format(i=1).replace("w = [650, -100, 400, 90, 0, 180]\n", poses)
    with pytest.raises(CellError, match=r"station\[0\]\.poses: 1001 poses; at most 1000 per station"):
        load_cell(write_cell(long_station))


def test_a_cell_file_that_is_a_pipe_or_too_large_is_refused_at_once(tmp_path):
    """A FIFO given as the cell would block a plain read for ever: refused before any byte is read; a file
    beyond the bound is refused without being read whole."""
    import os
    import subprocess
    import sys

    fifo = tmp_path / "cell.toml"
    os.mkfifo(fifo)
    code = "from codegen.model.cell import load_cell; import sys; load_cell(sys.argv[1])"
    run = subprocess.run([sys.executable, "-c", code, str(fifo)], capture_output=True, text=True, timeout=60)
    assert run.returncode != 0 and "not a regular file (a folder, pipe or device)" in run.stderr
    big = tmp_path / "big.toml"
    with big.open("wb") as handle:
        handle.truncate((64 << 20) + 1)
    with pytest.raises(CellError, match="larger than 64 MiB"):
        load_cell(big)
