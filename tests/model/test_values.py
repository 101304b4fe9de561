"""Number keys of the cell model: huge integers, whole numbers, angles, the tool's mass and the motion's speeds."""

from __future__ import annotations

import subprocess
import sys

import pytest
from support.cells import EXAMPLES

from codegen.model.cell import CellError, load_cell
from codegen.model.validate import Validator

HUGE = "1" + "0" * 400  # a 400-digit integer: beyond a float64


def edited(tmp_path, example: str, old: str, new: str):
    """The example cell with one change (old must occur in it), written to tmp_path."""
    text = EXAMPLES[example].read_text(encoding="utf-8")
    assert old in text, f"{example}: {old!r} not found"
    path = tmp_path / f"{example}.toml"
    path.write_text(text.replace(old, new, 1), encoding="utf-8")
    return path


def error_of(path) -> str:
    with pytest.raises(CellError) as info:
        load_cell(path)
    return str(info.value)


def run_cli(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "codegen", *args], capture_output=True, text=True, timeout=120)


@pytest.mark.parametrize("command", ["generate", "pallet"])
def test_a_400_digit_integer_is_one_message_naming_the_key(tmp_path, command):
    """Found by a fault probe: OverflowError in the number check, exit 1 with a traceback."""
    path = edited(tmp_path, "eur_pallet", "size = [1200.0, 800.0]", f"size = [{HUGE}, 78.0]")
    args = [command, str(path)] + (["--out", str(tmp_path / "out")] if command == "generate" else [])
    proc = run_cli(*args)
    assert proc.returncode == 2, proc.stderr
    assert "Traceback" not in proc.stderr
    assert "pallet[0].size[0]: expected a finite number, got an integer of 401 digits" in proc.stderr
    assert not (tmp_path / "out").exists()


def test_an_integer_too_long_for_python_to_read_is_named(tmp_path):
    """tomllib raises ValueError (not its TOMLDecodeError) for an integer of more than 4300 digits."""
    path = edited(tmp_path, "belt_pick", "timeout_s = 0.5", "timeout_s = 1" + "0" * 5000)
    assert "a number with thousands of digits" in error_of(path)


@pytest.mark.parametrize(
    ("old", "new", "says"),
    [
        ("mass_kg = 1.2", f"mass_kg = {HUGE}", "cell.tool.mass_kg: expected a finite number, got an integer of 401"),
        ("speed_mm_s = 500.0", f"speed_mm_s = -{HUGE}", "cell.motion.speed_mm_s: expected a finite number"),
        ("origin = [799.973,", f"origin = [{HUGE},", "conveyor.origin[0]: expected a finite number"),
        ("window_mm = [-150.0,", f"window_mm = [-{HUGE},", "conveyor.pick.window_mm[0]: expected a finite number"),
    ],
)
def test_huge_integers_in_other_sections_are_named(tmp_path, old, new, says):
    assert says in error_of(edited(tmp_path, "belt_pick", old, new))


def test_validator_integer_refuses_floats_booleans_and_out_of_range():
    ctx = Validator("cell.toml")
    assert ctx.integer({"n": 24}, "n", "x.n", 16, 32) == 24
    assert ctx.integer({}, "n", "x.n", 16, 32, default=32) == 32
    for value, says in [
        (16.0, "x.n: expected a whole number (no decimal point) in 16..32, got the number 16.0"),
        (True, "got a boolean"),
        (40, "expected a whole number in 16..32, got the number 40"),
        (int(HUGE), "got an integer of 401 digits"),
    ]:
        with pytest.raises(CellError, match=r"^cell\.toml: ") as info:
            ctx.integer({"n": value}, "n", "x.n", 16, 32)
        assert says in str(info.value)
    with pytest.raises(CellError, match=r"x\.n: missing"):
        ctx.integer({}, "n", "x.n", 16, 32)


def test_validator_angles_within_one_turn():
    ctx = Validator("cell.toml")
    assert ctx.angles((0.0, -360.0, 360.0), "a") == (0.0, -360.0, 360.0)
    assert ctx.angles((6.28,), "a", "rad") == (6.28,)
    with pytest.raises(CellError, match=r"a: angles must be within \+-360 deg: .* 64 deg"):
        ctx.angles((0.0, 0.0, 999999900.0), "a")
    with pytest.raises(CellError, match=r"r: angles must be within \+-6.28319 rad"):
        ctx.angles((7.0,), "r", "rad")


def test_a_tools_c_of_1e9_is_refused(tmp_path):
    """KUKA missed the tool's poses with c = 1e9 (the same turn as c = 280 in exact arithmetic)."""
    path = edited(tmp_path, "laser_tcp", "tcp = [0.0, 0.0, 180.0, 0.0, 0.0, 0.0]", "tcp = [0.0, 0.0, 180.0, 0, 0, 1e9]")
    assert "cell.tool.tcp: orientation values must be within +-360 deg" in error_of(path)


def test_a_50_kg_tool_on_a_5_kg_ur5e_is_refused(tmp_path):
    path = edited(tmp_path, "testmat_pallet", "mass_kg = 0.8", "mass_kg = 50.0")
    says = error_of(path)
    assert "cell.tool.mass_kg: 50 kg is more than the UR5e's payload of 5 kg (cell.robot.ur" in says
    # the tool and the pallet's 0.05 kg box within the payload together
    assert load_cell(edited(tmp_path, "testmat_pallet", "mass_kg = 0.8", "mass_kg = 4.9")).robot.tool.mass_kg == 4.9


def test_a_custom_arms_payload_is_the_limit(tmp_path):
    arm = (
        'kuka = { model = "Small", family = "opw", payload_kg = 1.0, params = { a1 = 25, a2 = -35, b = 0, c1 = 400, '
        "c2 = 560, c3 = 515, c4 = 80, offsets_deg = [0, 90, 0, 0, 0, 0], signs = [-1, 1, 1, -1, 1, -1] }, "
        "limits_deg = [[-170, 170], [-190, 45], [-120, 156], [-185, 185], [-120, 120], [-350, 350]], "
        "home_deg = [0, -90, 90, 0, 90, 0] }"
    )
    path = edited(tmp_path, "belt_pick", 'kuka = "KR 10 R1100 sixx"', arm)
    assert "cell.tool.mass_kg: 1.2 kg is more than the Small's payload of 1 kg (cell.robot.kuka, its table)" in (
        error_of(path)
    )


@pytest.mark.parametrize(
    ("old", "new", "says"),
    [
        # the programs write the mass to 3 decimals: 1e-300 kg became "M 0.000" in KRL's LOAD
        ("mass_kg = 1.5", "mass_kg = 1e-300", "cell.tool.mass_kg: expected a mass in [0.001, 1000] kg"),
        # and the speeds to 0.1 mm/s: 1e-300 mm/s became $VEL.CP = 0.0000
        ("work_speed_mm_s = 50.0", "work_speed_mm_s = 1e-300", "cell.motion.work_speed_mm_s: must be in [1, 5000]"),
        ("speed_mm_s = 250.0", "speed_mm_s = 0.5", "cell.motion.speed_mm_s: must be in [1, 5000] mm/s"),
    ],
)
def test_values_the_programs_would_write_as_zero_are_refused(tmp_path, old, new, says):
    assert says in error_of(edited(tmp_path, "laser_tcp", old, new))


@pytest.mark.parametrize(
    ("old", "new", "says"),
    [
        ("max_iterations = 10", "max_iterations = 10.0", "cell.refine.max_iterations: expected a whole number"),
        ("max_iterations = 10", f"max_iterations = {HUGE}", "cell.refine.max_iterations: expected a whole number"),
    ],
)
def test_the_frame_refinements_count_is_a_whole_number(tmp_path, old, new, says):
    assert says in error_of(edited(tmp_path, "thermometer_bench", old, new))


@pytest.mark.parametrize(
    ("config", "says"),
    [
        ("[station.config.abb]\nchuck = [0, 0, 0.0, 0]\n", "config.abb.chuck[2]: expected a whole number"),
        ("[station.config.abb]\nchuck = [0, 0, 9, 0]\n", "config.abb.chuck[2]: expected a whole number in -8..7"),
        ("[station.config.kuka]\nchuck = { s = 2.0, t = 0 }\n", "config.kuka.chuck.s: expected a whole number"),
        (f"[station.config.kuka]\nchuck = {{ s = 2, t = {HUGE} }}\n", "config.kuka.chuck.t: expected a whole number"),
    ],
)
def test_a_poses_configuration_takes_whole_numbers_in_range(tmp_path, config, says):
    taught = "chuck = [738.5, -112.3, 305.2, 90.0, 0.0, 180.0]\n"
    assert says in error_of(edited(tmp_path, "agv_machine_tending", taught, taught + config))
