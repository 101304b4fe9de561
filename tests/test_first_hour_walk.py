"""What the first-hour walks (a fresh clone, the README and the docs only: a UR5e tending a lathe, a UR10e at a
mill, KUKA pallet cells) stumbled on, each with the cell as the walk wrote it."""

from __future__ import annotations

import math
import re
from pathlib import Path

import pytest

from codegen.model.cell import load_cell

LATHE = """\
[cell]
name = "lathe_tending"
targets = ["ur"]
pose_format = "xyzabc"

[cell.camera]
angle_sign = 1

[cell.robot]
ur = "UR5e"

[cell.tool]
tcp = [0.0, 0.0, 160.0, 0.0, 0.0, 0.0]
mass_kg = 1.1
cog_mm = [0.0, 0.0, 60.0]
radius_mm = 30.0

[cell.limits]
max_shift_mm = 15.0
max_rotation_deg = 5.0

[[station]]
id = 7
name = "lathe"
mark = [520.0, -180.0, 0.5]
[station.poses]
approach = [540.0, -120.0, 380.0, 0.0, 0.0, 180.0]
chuck = [560.0, -110.0, 260.0, 0.0, 0.0, 180.0]
"""


def test_a_configuration_change_prints_the_joints_rounded(write_cell):
    """With the chuck pose left out, the station's retreat changes configuration for a reading: the refusal printed
    both joint sets with 16 digits each ("153.5271831256482, -81.93119270557679, ..."); now to 0.1 deg."""
    from codegen.generate import GenerateError, check_envelope

    cell = load_cell(write_cell(LATHE.replace("chuck = [560.0, -110.0, 260.0, 0.0, 0.0, 180.0]\n", "")))
    with pytest.raises(GenerateError) as info:
        check_envelope(cell, None)
    said = str(info.value)
    assert (
        "pose 'retreat' (ur, UR5e): the arm would change configuration (taught [153.5, -81.9, 66.2, -74.3, -90.0, "
        "243.5], here [" in said
    )
    assert "153.527" not in said


CARTONS = """\
[cell]
name = "carton_pal"
targets = ["kuka"]

[cell.robot]
kuka = "KR 210 R2700 extra"

[cell.tool]
tcp = [0.0, 0.0, 220.0, 0.0, 0.0, 0.0]
mass_kg = 5.0
cog_mm = [0.0, 0.0, 100.0]
radius_mm = 30.0

[cell.world]
floor_z_mm = -600.0
solids.conveyor = { box = [1000.0, 400.0, 450.0], pose = [1600.0, 0.0, -375.0, 0.0, 0.0, 0.0] }

[cell.io]
output = { kuka = 17 }
feedback = { kuka = 18 }
timeout_s = 2.0

[[pallet]]
name = "half"
frame = { origin = [-400.0, 1200.0, -456.0], x_point = [400.0, 1200.0, -456.0], xy_point = [-400.0, 1800.0, -456.0] }
size = [800.0, 600.0]
box = [300.0, 200.0, 150.0]
layers = 6
cycle = ["a", "b"]
tool_orientation = [0.0, 0.0, 180.0]
entry_dz = 200.0
approach = [0.0, 0.0, 50.0]
pick = [1300.0, 0.0, 150.0, 0.0, 0.0, 180.0]
box_mass_kg = 8.0

[pallet.io]
part_present = { kuka = 19 }
pallet_present = { kuka = 20 }

[pallet.patterns]
a = { family = "interlock" }
b = { family = "interlock", mirror = true }
"""


def test_a_pallet_at_the_wrist_singularity_is_told_what_to_change(write_cell):
    """A half pallet on the floor 1.2 m beside a KR 210: its low boxes are reached with the tool in line with the
    forearm. The refusal gave the margins and no fix; it says what the wrist singularity is and which key moves the
    work away from it, and the fix holds: the pallet 200 mm farther out (or 156 mm higher) reaches."""
    from codegen.generate import GenerateError, check_envelope

    with pytest.raises(GenerateError) as info:
        check_envelope(load_cell(write_cell(CARTONS)), None)
    said = str(info.value)
    assert "the wrist 2.2 deg from its singularity; the cell asks 5 and 5 deg" in said
    assert said.endswith(
        ": axis 5 near 0 deg lines up axes 4 and 6 (the tool in line with the forearm); place the pallet (its frame) "
        "farther from or nearer to the arm's base, or higher or lower"
    )
    farther = CARTONS.replace("1200.0, -456.0]", "1400.0, -456.0]").replace("1800.0, -456.0]", "2000.0, -456.0]")
    assert check_envelope(load_cell(write_cell(farther)), None)
    higher = CARTONS.replace("-456.0]", "-300.0]")
    assert check_envelope(load_cell(write_cell(higher)), None)


@pytest.mark.parametrize(
    ("old", "new", "said"),
    [
        (
            "box = [300.0, 200.0, 150.0]",
            "box = [0.3, 0.2, 0.15]",
            "pallet[0].box: 0.3 x 0.2 x 0.15 mm: given in metres? Sizes are mm: 0.3 m is 300 mm",
        ),
        (
            "size = [800.0, 600.0]",
            "size = [0.8, 0.6]",
            "pallet[0].size: 0.8 x 0.6 mm: given in metres? Sizes are mm: 0.8 m is 800 mm",
        ),
    ],
)
def test_a_box_or_pallet_size_in_metres_is_asked_about(write_cell, old, new, said):
    """The box written in metres was refused as "7999994 boxes of 0.3 x 0.2 mm make this family's layer"."""
    from codegen.model.cell import CellError

    with pytest.raises(CellError) as info:
        load_cell(write_cell(CARTONS.replace(old, new, 1)))
    assert said in str(info.value) and "line " in str(info.value)


def test_a_tool_orientation_that_points_the_tool_up_is_refused_at_its_key(write_cell):
    """tool_orientation = [0, 0, 0] (the tool's z up) was refused at generate as "out of reach ... its orientation, a
    joint limit or the arm's own base rules it out" at layer 1 box 1; it is the key's mistake, said at its line."""
    from codegen.model.cell import CellError

    text = CARTONS.replace("tool_orientation = [0.0, 0.0, 180.0]", "tool_orientation = [0.0, 0.0, 0.0]")
    with pytest.raises(CellError) as info:
        load_cell(write_cell(text))
    assert (
        "line 30: pallet[0].tool_orientation: the tool's z points up (a, b, c = 0, 0, 0): the TCP grips the box at its "
        "top, its z into the box, so it points down into the pallet (0, 0, 180 points it straight down)"
    ) in str(info.value)
    tilted = CARTONS.replace("tool_orientation = [0.0, 0.0, 180.0]", "tool_orientation = [0.0, 10.0, 170.0]")
    assert load_cell(write_cell(tilted)).sections["pallet"][0].tool_orientation == (0.0, 10.0, 170.0)


# The third walk: a UR10e at a mill (a point station and a frame station, hand-eye calibrated) and a KR 10 pallet cell
# of cartons, each as tests/kinds/cells/walk3_*.toml holds it.
WALK3 = Path(__file__).parent / "kinds" / "cells"


def test_a_default_refused_says_it_is_not_in_the_file(write_cell):
    """A 0.052 mm pixel makes the default refine tolerance (0.02 mm) too fine. The refusal read "line 3:
    cell.refine.tolerance_mm: 0.02 mm is finer ..." at the [cell] header of a file without [cell.refine]: where the
    walk looked for a key it had not written. It says the key is not in the file and is its default."""
    from codegen.model.cell import CellError

    text = (WALK3 / "walk3_mill.toml").read_text(encoding="utf-8")
    start = text.index("[cell.refine]")
    without = text[:start] + text[text.index("\n\n", start) + 2 :]
    with pytest.raises(CellError) as info:
        load_cell(write_cell(without))
    assert ": line 4: cell.refine.tolerance_mm (not in the file: its default): 0.02 mm is finer than the camera" in str(
        info.value
    )
    with pytest.raises(CellError) as info:  # written in the file: its own line, no note
        load_cell(write_cell(text.replace("tolerance_mm = 0.03", "tolerance_mm = 0.02")))
    assert "cell.refine.tolerance_mm: 0.02 mm is finer" in str(info.value)
    assert "not in the file" not in str(info.value)


@pytest.mark.parametrize(
    ("cell", "old", "new", "said"),
    [
        (
            "walk3_mill.toml",
            "retreat_mm = 60.0",
            "retreat_mn = 60.0",
            "cell.motion.retreat_mn: unknown key (did you mean ",
        ),
        ("walk3_mill.toml", "[cell.tool]", "[cell.tools]", "cell.tools: unknown key (did you mean 'tool'?); allowed: "),
        (
            "walk3_pallet.toml",
            "angle_sense =",
            "angle_sens =",
            "pallet[0].angle_sens: unknown key (did you mean 'angle_",
        ),
    ],
)
def test_a_typed_key_names_the_key_meant(write_cell, cell, old, new, said):
    """A key typed one letter off was refused with the list of the table's keys alone (25 of them for a pallet), the
    one meant to be found among them; the refusal names it."""
    from codegen.model.cell import CellError

    text = (WALK3 / cell).read_text(encoding="utf-8")
    assert old in text
    with pytest.raises(CellError) as info:
        load_cell(write_cell(text.replace(old, new, 1)))
    assert said in str(info.value)
    meant = {"retreat_mn": "'retreat_mm'?)", "tools": "'tool'?)", "angle_sens": "'angle_sense'?)"}
    assert meant[new.split()[0].strip("[]").split(".")[-1]] in str(info.value)


def test_a_missing_signal_shows_it_for_the_cells_controller(write_cell):
    """The pallet's pallet_present left out: the example shown was `pallet_present = { ... }`, no help to write it;
    it is the signal per target of the cell, with the range the controller takes."""
    from codegen.model.cell import CellError

    text = (WALK3 / "walk3_pallet.toml").read_text(encoding="utf-8")
    with pytest.raises(CellError) as info:
        load_cell(write_cell(text.replace("pallet_present = { kuka = 12 }\n", "")))
    assert str(info.value).endswith(
        "pallet[0].io.pallet_present: missing: on when the pallet stands in place. For example:\n"
        "    pallet_present = { kuka = <integer [1, 4096]> }"
    )


def test_a_centre_of_gravity_in_metres_is_asked_about(write_cell):
    """cog_mm = [0, 0, 0.07] (70 mm written in metres) on a 180 mm tool was taken: the programs' load put its mass at
    the flange. It is asked about, as the TCP is; the flange itself (0, 0, 0) stays a centre of gravity."""
    from codegen.model.cell import CellError

    text = (WALK3 / "walk3_mill.toml").read_text(encoding="utf-8")
    with pytest.raises(CellError) as info:
        load_cell(write_cell(text.replace("cog_mm = [0.0, 0.0, 70.0]", "cog_mm = [0.0, 0.0, 0.07]")))
    assert (
        "line 23: cell.tool.cog_mm: the centre of gravity is 0.07 mm from the flange, the TCP 180 mm: given in metres? "
        "cog_mm is mm in the flange frame: 0.07 m is 70 mm"
    ) in str(info.value)
    at_flange = load_cell(write_cell(text.replace("cog_mm = [0.0, 0.0, 70.0]", "cog_mm = [0.0, 0.0, 0.0]")))
    assert at_flange.robot.tool.cog_mm == (0.0, 0.0, 0.0)


@pytest.mark.parametrize(
    ("cell", "program", "said"),
    [
        ("walk3_pallet.toml", "mill_cell.script", "a program for ur, and cell tray_stack ("),
        ("walk3_mill.toml", "pal_tray.src", "a program for kuka, and cell mill_cell ("),
    ],
)
def test_a_program_for_a_target_the_cell_lacks_is_refused(tmp_path, cell, program, said):
    """The walk's UR program given to verify with the KUKA pallet cell ended in a traceback (KeyError: 'ur'); its
    KUKA pallet program given with the UR cell ran 2,096 cases as the station program and printed 2,559 failures.
    Each is one message naming the file and the cell's targets, exit 2."""
    from click.testing import CliRunner

    from codegen.cli import main

    (tmp_path / cell).write_text((WALK3 / cell).read_text(encoding="utf-8"), encoding="utf-8")
    (tmp_path / program).write_text("def p():\n  sleep(1)\nend\n" if program.endswith(".script") else "DEF P()\nEND\n")
    result = CliRunner().invoke(main, ["verify", str(tmp_path / cell), str(tmp_path / program)])
    assert result.exit_code == 2 and isinstance(result.exception, SystemExit), result.output
    assert f"Error: {tmp_path / program}: {said}" in result.output
    assert "has no" in result.output and "(its targets: " in result.output


UR_METRES = """\
[cell]
name = "urfmt"
targets = ["ur"]
pose_format = "ur"
[cell.camera]
angle_sign = 1
[cell.robot]
ur = "UR10e"
[cell.tool]
tcp = [0.0, 0.0, 0.18, 0.0, 0.0, 0.0]
mass_kg = 1.4
cog_mm = [0.0, 0.0, 70.0]
radius_mm = 35.0
[cell.limits]
max_shift_mm = 20.0
max_rotation_deg = 8.0
[[station]]
id = 11
name = "mill_vise"
mark = [760.0, -240.0, 2.0]
[station.poses]
approach = [0.70, -0.150, 0.450, 3.1416, 0.0, 0.0]
vise = [0.780, -0.160, 0.310, 3.1416, 0.0, 0.0]
"""


def test_a_tool_longer_than_the_arm_reaches_is_asked_about(write_cell):
    """The mill station written with pose_format = "ur" and the TCP slipped a digit (tcp = [0, 0, 1.8, ...] for
    0.18): taken as a 1.8 m tool and refused only at generate, about the station's pose ("the flange would be at (700,
    -150, 2250) mm ... move the pose (or the arm) closer"). The tool's key says it as the cell is read."""
    from codegen.generate import check_envelope
    from codegen.model.cell import CellError

    assert check_envelope(load_cell(write_cell(UR_METRES)), None)
    with pytest.raises(CellError) as info:
        load_cell(write_cell(UR_METRES.replace("[0.0, 0.0, 0.18,", "[0.0, 0.0, 1.8,")))
    assert (
        "line 10: cell.tool.tcp: the TCP is 1,800 mm from the flange, longer than the UR10e's reach of 1,300 mm "
        '(cell.robot.ur): a value in another unit? (pose_format = "ur" takes x y z m'
    ) in str(info.value)


def test_the_walks_mill_cell_generates():
    """The walk's UR cell as it ended: every pose reached for every accepted reading (generate's proof)."""
    from codegen.generate import check_envelope

    assert check_envelope(load_cell(WALK3 / "walk3_mill.toml"), None)


def test_diff_without_differences_says_so(tmp_path):
    """`codegen diff` of the walk's pallet cell against its fresh output printed nothing and exited 0: no sign that it
    compared anything. It says so on stderr; stdout stays the diff alone (empty)."""
    from click.testing import CliRunner

    from codegen.cli import main

    cell = tmp_path / "walk3_pallet.toml"
    cell.write_text((WALK3 / "walk3_pallet.toml").read_text(encoding="utf-8"), encoding="utf-8")
    assert CliRunner().invoke(main, ["generate", str(cell), "--out", str(tmp_path / "out")]).exit_code == 0
    result = CliRunner().invoke(main, ["diff", str(cell), "--out", str(tmp_path / "out")])
    assert result.exit_code == 0 and result.stdout == ""
    assert (
        result.stderr
        == f"no differences: the files in {tmp_path / 'out'} are what codegen generate writes for cell tray_stack\n"
    )


def test_a_frame_case_names_its_camera_in_words():
    """A frame case's reading named the camera as a Python object (`CameraModel(scale_error=0.03, ...)`); it now
    says what differs from a perfect camera."""
    from codegen.kinds.station.modes.frame import FrameCase, FrameMode
    from codegen.sim.camera import CameraModel

    case = FrameCase(12, 1.5, -2.0, 0.5, CameraModel(scale_error=0.03, rotation_error_deg=0.5, fault_at_photo=2))
    text = FrameMode.describe_reading(case)
    assert text.endswith("camera scale off 3 %, turned 0.5 deg, photo 2 fails"), text
    assert str(CameraModel()) == "exact"


def test_slow_kinds_rate_is_not_printed_as_zero():
    """The walk's pallet verified at 0.43 cases/s and the table printed 0."""
    from codegen.verify.report import _rate

    assert [_rate(v) for v in (0.43, 12.345, 4321.2, None)] == ["0.43", "12.3", "4321", "0"]


def _walk3_mill_edited(tmp_path: Path, old: str, new: str) -> list[str]:
    """The walk's mill cell generated into tmp_path, its UR program with `old` replaced by `new` (once): the verify
    command line for the edited program."""
    from click.testing import CliRunner

    from codegen.cli import main

    cell = tmp_path / "walk3_mill.toml"
    cell.write_text((WALK3 / "walk3_mill.toml").read_text(encoding="utf-8"), encoding="utf-8")
    assert CliRunner().invoke(main, ["generate", str(cell), "--out", str(tmp_path / "out")]).exit_code == 0
    program = tmp_path / "out" / "mill_cell" / "ur" / "mill_cell.script"
    text = program.read_text(encoding="utf-8")
    assert text.count(old) == 1
    edited = tmp_path / "mill_cell.script"
    edited.write_text(text.replace(old, new), encoding="utf-8")
    return ["verify", str(cell), str(edited), "--cases", "2", "--jobs", "1"]


def test_a_slower_linear_move_after_a_joint_move_to_solved_joints_shows_its_time(tmp_path):
    """The vise's linear move follows `movej(get_inverse_kin(...))`: the interpreter left that move's pose unknown, so
    the linear move took an assumed 1 s whatever its speed, and its speed edit (0.04 -> 0.03 m/s) with a 0.5 s sleep
    showed as 0.50 s later. The joint move's pose is the forward kinematics of the joints it solved: the linear move
    from approach to vise (rigidly corrected alike: its length is the taught poses') takes L / v."""
    from click.testing import CliRunner

    from codegen.cli import main

    old = "    movel(pose_trans(corr, p11_vise), a=1.2, v=0.0400)\n"
    args = _walk3_mill_edited(tmp_path, old, old.replace("0.0400", "0.0300") + "    sleep(0.5)\n")
    result = CliRunner().invoke(main, args)
    length_mm = math.dist([700.0, -150.0, 450.0], [780.0, -160.0, 310.0])  # walk3_mill.toml: approach, vise
    slower_s = length_mm / 30.0 - length_mm / 40.0
    assert f"EDIT effect: reaches move 3 (line 171) {slower_s:.2f} s later than the generated program" in result.stdout
    assert f"EDIT effect: the run takes {slower_s + 0.5:.2f} s longer" in result.stdout


def test_a_failing_programs_arm_line_says_which_runs_it_counts(tmp_path):
    """The arm's line of a program with mismatches counted only its matching runs' moves and gave their least margin
    as the program's. It says it counts the matching runs and how many mismatching ones it leaves out; a program
    without mismatches keeps the plain line."""
    from click.testing import CliRunner

    from codegen.cli import main

    old = "    movel(pose_trans(corr, p11_vise), a=1.2, v=0.0400)\n"
    result = CliRunner().invoke(main, _walk3_mill_edited(tmp_path, old, old.replace("0.0400", "0.0300")))
    failing = re.search(r"^mill_cell +station +ur +\d+ +(\d+) ", result.stdout, re.M)
    assert failing and int(failing.group(1)) > 0
    arm = [line for line in result.stdout.splitlines() if line.startswith("arm ur mill_cell:")]
    assert len(arm) == 1
    assert f" moves solved to joints in the runs that match (not the {failing.group(1)} that mismatch); " in arm[0]
    fresh = CliRunner().invoke(main, ["verify", str(tmp_path / "walk3_mill.toml"), "--cases", "2", "--jobs", "1"])
    assert fresh.exit_code == 0
    plain = [line for line in fresh.stdout.splitlines() if line.startswith("arm ")]
    assert plain and all(" joints; least margin " in line for line in plain)


def test_a_kuka_speed_edit_is_one_mismatch_named_as_the_controller_names_it(tmp_path):
    """The walk's pallet program with its work speed edited ($VEL.CP 0.05 -> 0.04) printed ten MISMATCH lines, one
    per case category and box, each naming the internal key `vel_cp`. The same difference at the same line is one
    line naming the categories it was met in, and the setting is the controller's $VEL.CP."""
    from click.testing import CliRunner

    from codegen.cli import main

    cell = tmp_path / "walk3_pallet.toml"
    cell.write_text((WALK3 / "walk3_pallet.toml").read_text(encoding="utf-8"), encoding="utf-8")
    assert CliRunner().invoke(main, ["generate", str(cell), "--out", str(tmp_path / "out")]).exit_code == 0
    program = tmp_path / "out" / "tray_stack" / "kuka" / "pal_tray.src"
    old = "    $VEL.CP = 0.0500 ; m/s, the cell's work speed (50.0 mm/s): the approach and the target\n"
    text = program.read_text(encoding="utf-8")
    assert text.count(old) == 1
    program.write_text(text.replace(old, old.replace("0.0500", "0.0400")), encoding="utf-8")
    result = CliRunner().invoke(main, ["verify", str(cell), str(program), "--cases", "1", "--jobs", "1"])
    assert result.exit_code == 1
    assert "vel_cp" not in result.stdout
    assert "EDIT effect: moves 8-439 (from line 242) $VEL.CP 0.04, generated 0.05" in result.stdout
    shown = [line for line in result.stdout.splitlines() if line.startswith("  MISMATCH")]
    assert len(shown) == 1, shown
    failing = int(re.search(r"^pal_tray +pallet +kuka +\d+ +(\d+) ", result.stdout, re.M).group(1))
    said = re.fullmatch(
        rf"  MISMATCH (\w+) .*: move \d+ \(layer \d+ box \d+ approach, line 242\): \$VEL\.CP 0\.04, expected 0\.05 "
        rf"\(and {failing - 1} more cases alike; in ([\w, ]+)\)",
        shown[0],
    )
    assert said, shown[0]
    categories = said.group(2).split(", ")
    assert said.group(1) == categories[0] and len(categories) == len(set(categories)) > 1
    assert {"full_stack", "restart", "held_at_start"} <= set(categories)


def test_a_station_is_named_by_its_entry_as_the_loader_names_it(tmp_path, write_cell):
    """Generate named a station by its id (`station[8] 'lathe!'`) where the loader and the docs name the entry by its
    place from 0 (`station[1].poses`): a station with id 8, second in the file, was looked for as the ninth. Every
    station message names the entry as the loader does."""
    from click.testing import CliRunner

    from codegen.cli import main
    from codegen.controllers import get_target
    from codegen.kinds.station.modes.point import PointMode
    from codegen.kinds.station.section import stations_of

    second = LATHE[LATHE.index("[[station]]") :].replace("id = 7", "id = 8").replace('"lathe"', '"lathe!"')
    cell = write_cell(LATHE + "\n" + second)
    result = CliRunner().invoke(main, ["generate", str(cell), "--out", str(tmp_path / "out")])
    assert result.exit_code == 2
    assert "ur: station[1] 'lathe!' and station[0] 'lathe' both map to the identifier st_lathe; rename one" in (
        result.output
    )

    class Names:  # an emitter that keeps the origins the mode names its identifiers by
        origins: list[str] = []

        def identifier(self, prefix, name, origin):
            self.origins.append(origin)
            return prefix + name

        def number(self, value, decimals):
            return value

        def string(self, text):
            return text

    model = load_cell(cell)
    PointMode.station_context(model, stations_of(model)[1], get_target("ur"), Names())
    assert Names.origins == ["station[1] 'lathe!' mark"]


def test_the_frame_tolerance_hint_names_the_key_and_its_value_loads(write_cell):
    """A tolerance finer than the camera resolves said "set at least 0.0208 mm" without the key (the walk's cell
    left [cell.refine] out: the default was refused). The hint names the table and key, and the value it gives
    loads."""
    from codegen.model.cell import CellError

    text = (WALK3 / "walk3_mill.toml").read_text(encoding="utf-8")
    assert text.count("tolerance_mm = 0.03\n") == 1
    with pytest.raises(CellError) as info:
        load_cell(write_cell(text.replace("tolerance_mm = 0.03\n", "tolerance_mm = 0.01\n")))
    hint = re.search(r"; set \[cell\.refine\] tolerance_mm = (\d+\.\d+) or more \(", str(info.value))
    assert hint, str(info.value)
    assert load_cell(write_cell(text.replace("tolerance_mm = 0.03\n", f"tolerance_mm = {hint.group(1)}\n")))
