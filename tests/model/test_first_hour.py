"""What a new user's first cell file gets told: values in the wrong unit, and a missing key or table explained with
what it is for and a minimal example, at its line."""

from __future__ import annotations

import pytest
from support.cells import MINIMAL_CELL

from codegen.model.cell import CellError, load_cell

ROBOT = '[cell.robot]\nur = "UR10e"\nkuka = "KR 10 R1100 sixx"\nabb = "IRB 1600-10/1.45"\n'
TOOL = ROBOT + "[cell.tool]\ntcp = [0.0, 0.0, 200.0, 0.0, 0.0, 0.0]\nmass_kg = 1.5\ncog_mm = [0.0, 0.0, 80.0]\n"
WITH_TOOL = MINIMAL_CELL.replace("[cell.camera]", TOOL + "[cell.camera]")


def error(write_cell, text: str) -> str:
    with pytest.raises(CellError) as info:
        load_cell(write_cell(text))
    return str(info.value)


def test_the_cell_with_its_tool_loads(write_cell):
    assert load_cell(write_cell(WITH_TOOL)).robot.tool.tcp[2] == 200.0


def test_a_tcp_in_metres_in_a_millimetre_cell_says_so(write_cell):
    message = error(write_cell, WITH_TOOL.replace("tcp = [0.0, 0.0, 200.0,", "tcp = [0.0, 0.0, 0.2,"))
    assert "line 10: cell.tool.tcp: the TCP is 0.2 mm from the flange: given in metres?" in message
    assert "0.2 m is 200 mm" in message


def test_a_mark_in_metres_says_so(write_cell):
    message = error(write_cell, WITH_TOOL.replace("mark = [600.0, -250.0, 2.0]", "mark = [0.6, -0.25, 2.0]"))
    assert "station[0].mark: x, y lie 0.6 mm from the robot's base: given in metres?" in message
    assert "0.6 m is 600 mm" in message


def test_a_mark_in_metres_farther_than_a_metre_says_so_too(write_cell):
    message = error(write_cell, WITH_TOOL.replace("mark = [600.0, -250.0, 2.0]", "mark = [1.2, -0.25, 2.0]"))
    assert "station[0].mark: x, y lie 1.2 mm from the robot's base: given in metres?" in message


def test_a_taught_pose_in_metres_says_so_at_its_key(write_cell):
    text = WITH_TOOL.replace("chuck = [700.0, -100.0, 300.0,", "chuck = [0.7, -0.1, 0.3,")
    message = error(write_cell, text)
    assert "station[0].poses.chuck: x, y, z lie within 0.7 mm of the robot's base: given in metres?" in message
    assert "0.7 m is 700 mm" in message


def test_metres_in_a_ur_cell_are_its_unit(write_cell):
    """pose_format = "ur" takes metres: a pose of 0.7 m is no slip (its orientation is radians as well)."""
    ur = WITH_TOOL.replace('pose_format = "xyzabc"', 'pose_format = "ur"').replace(
        "tcp = [0.0, 0.0, 200.0, 0.0, 0.0, 0.0]", "tcp = [0.0, 0.0, 0.2, 0.0, 0.0, 0.0]"
    )
    taught = (
        "approach = [650.0, -100.0, 400.0, 90.0, 0.0, 180.0]",
        "chuck = [700.0, -100.0, 300.0, 90.0, 0.0, 180.0]",
        "vise = [700.0, 50.0, 260.0, -90.0, 15.0, 180.0]",
    )
    for pose in taught:
        assert pose in ur
        name, values = pose.split(" = ")
        metres = [float(v) / 1000.0 for v in values.strip("[]").split(", ")[:3]]
        ur = ur.replace(pose, f"{name} = [{metres[0]}, {metres[1]}, {metres[2]}, 0.0, 3.14159, 0.0]")
    assert load_cell(write_cell(ur)).pose_format == "ur"


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        (
            "origin = [650.0, -50.0, 50.0], x_point = [750.0, -50.0, 50.0], xy_point = [650.0, 30.0, 50.0]",
            "origin = [0.65, -0.05, 0.05], x_point = [0.75, -0.05, 0.05], xy_point = [0.65, 0.03, 0.05]",
            "pallet[0].frame.origin: x, y, z lie within 0.65 mm of the robot's base: given in metres? The pallet "
            "frame's points are mm in the base frame: 0.65 m is 650 mm",
        ),
        (
            "pick = [600.0, 300.0, 50.0,",
            "pick = [0.6, 0.3, 0.05,",
            "pallet[0].pick: x, y, z lie within 0.6 mm of the robot's base: given in metres? Q is mm",
        ),
    ],
)
def test_a_pallet_in_metres_says_so_at_its_key(write_cell, old, new, message):
    from support.cells import EXAMPLES

    text = EXAMPLES["testmat_pallet"].read_text(encoding="utf-8")
    assert old in text
    assert message in error(write_cell, text.replace(old, new, 1))


def test_a_pose_of_another_format_says_what_the_cells_format_takes_and_which_it_would_be(write_cell):
    chuck = "chuck = [700.0, -100.0, 300.0, 90.0, 0.0, 180.0]"
    message = error(write_cell, WITH_TOOL.replace(chuck, "chuck = [700.0, -100.0, 300.0, 0, 1, 0, 0]"))
    said = 'station[0].poses.chuck: expected 6 numbers, got 7 (pose_format = "xyzabc" takes x y z mm, a b c deg'
    assert said in message
    assert '7 numbers are a pose of pose_format = "abb" (x y z mm, quaternion' in message
    abb = WITH_TOOL.replace('pose_format = "xyzabc"', 'pose_format = "abb"').replace(
        "tcp = [0.0, 0.0, 200.0, 0.0, 0.0, 0.0]", "tcp = [0.0, 0.0, 200.0, 1.0, 0.0, 0.0, 0.0]"
    )
    message = error(write_cell, abb)
    assert 'expected 7 numbers, got 6 (pose_format = "abb" takes x y z mm, quaternion' in message
    assert all(f'pose_format = "{name}"' in message for name in ("xyzabc", "ur", "dtrans"))
    five = WITH_TOOL.replace(chuck, "chuck = [700.0, -100.0, 300.0, 90.0, 0]")
    assert "expected 6 numbers, got 5 (pose_format" in error(write_cell, five)
    assert "5 numbers are" not in error(write_cell, five)


def test_a_ur_cell_given_millimetres_and_degrees_says_what_ur_takes(write_cell):
    ur = WITH_TOOL.replace('pose_format = "xyzabc"', 'pose_format = "ur"')
    message = error(write_cell, ur)
    assert "cell.tool.tcp: the TCP must be within 2000 mm of the flange" in message
    assert 'pose_format = "ur" takes x y z m, rotation vector rx ry rz rad' in message
    assert 'or set pose_format = "xyzabc"' in message
    poses = error(write_cell, ur.replace("tcp = [0.0, 0.0, 200.0,", "tcp = [0.0, 0.0, 0.2,"))
    assert "station[0].poses.approach: orientation values must be within +-6.28319 rad" in poses
    assert 'pose_format = "ur" takes' in poses


def test_a_missing_table_says_what_it_is_for_with_an_example_at_its_line(write_cell):
    without = MINIMAL_CELL.replace("[cell.limits]\nmax_shift_mm = 10.0\nmax_rotation_deg = 10.0\n", "")
    message = error(write_cell, without)
    assert "line 1: cell.limits: missing: How far a reading may move a station" in message
    assert "For example:\n    [cell.limits]\n    max_shift_mm = <mm (0, 100000]>" in message
    assert "max_rotation_deg = <deg (0, 180)>" in message


def test_a_missing_key_says_what_it_is_for_with_an_example(write_cell):
    message = error(write_cell, MINIMAL_CELL.replace("mark = [600.0, -250.0, 2.0]\n", ""))
    assert "station[0].mark: missing: where the camera saw the station's mark at calibration" in message
    assert "For example:\n    mark = [<number>, <number>, <number>]" in message
    named = error(write_cell, MINIMAL_CELL.replace('name = "bench"\n', ""))
    assert "cell.name: missing: the cell's name (the programs' folder). For example:\n    name = \"...\"" in named
