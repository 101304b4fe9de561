"""ABB RAPID target; the independent checker rapidchecker must accept every generated module."""

from rapidcheck import rapidchecker, rapidchecker_raw
from station_base import ArmTests, HaltGoesOnTests, MotionTests, StationTests, cell_text, replace_once

from codegen.model.cell import load_cell
from codegen.render import render

WORK = "MoveL vis_apply(corr, p1_chuck), vis_work, fine, vis_tool;"  # the work pose of station 1


class TestABB(StationTests, MotionTests, ArmTests, HaltGoesOnTests):
    target = "abb"
    motion_mutations = ["speed_x25", "zone_on_work_pose"]
    arm_mutations = ["robconf_changed", "check_always_on", "tool0", "light_tool", "out_of_reach", "no_home"]
    arm_stations = (1, 3)  # station 3's approach holds its robconf over the region: the program names it
    arm_words = {
        "robconf_changed": ("configuration [0, 0, 0, 0]",),
        "check_always_on": ("configuration",),
        "tool0": ("tool TOOL0", "a linear move would change the arm's configuration"),
        "light_tool": ("load",),
        "out_of_reach": ("out of reach", "cannot reach"),
        "no_home": ("moves, expected", "first motion"),
    }

    def mutate(self, mutation, text, dat):
        return {
            "swap_sin_cos": lambda: replace_once(text, "cos_phi := Cos(phi);", "cos_phi := Sin(phi);"),
            "flip_sign": lambda: replace_once(text, "phi := ANGLE_SIGN *", "phi := -ANGLE_SIGN *"),
            "drop_guard": lambda: replace_once(text, "IF dx * dx + dy * dy > MAX_SHIFT_SQ THEN", "IF FALSE THEN"),
            "calibration_number": lambda: replace_once(text, "612.400000", "612.450000"),
            "extra_dispatch_id": lambda: replace_once(text, "    CASE 1:\n", "    CASE 1, 20000:\n"),
            "halt_goes_on": lambda: replace_once(text, "    Stop;\n    EXIT;\n", "    Stop;\n"),  # in vis_stop
            "robconf_changed": lambda: replace_once(
                text, "0.701057385, 0.092295956], [-1, 0, -2, 0]", "0.701057385, 0.092295956], [0, 0, 0, 0]"
            ),
            "check_always_on": lambda: text.replace("ConfJ \\Off;", "ConfJ \\On;"),
            "tool0": lambda: text.replace("fine, vis_tool;", "fine, tool0;"),
            "light_tool": lambda: replace_once(text, "[1.500, [0.0000, 0.0000, 80.0000]", "[0.500, [0.0, 0.0, 80.0]"),
            "out_of_reach": lambda: replace_once(text, "p1_chuck := [[738.5000", "p1_chuck := [[2738.5000"),
            "no_home": lambda: replace_once(text, "    MoveAbsJ vis_home\\NoEOffs, v200, fine, vis_tool;\n", ""),
            "speed_x25": lambda: replace_once(text, WORK, WORK.replace("vis_work", "v1000")),
            "zone_on_work_pose": lambda: replace_once(text, WORK, WORK.replace("fine", "z200")),
        }[mutation]()


def test_rapidchecker_accepts_the_demo_module(tmp_path):
    (f,) = render(load_cell(), ["abb"])
    proc = rapidchecker(f.text, tmp_path / "demo.mod")
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "No RAPID format errors" in proc.stdout


def test_rapidchecker_accepts_hostile_names(tmp_path):
    cell_path = tmp_path / "cell.toml"
    cell_path.write_text(cell_text(['lathe "1"; ENDPROC', "mill\n!2 é"]), encoding="utf-8")
    (f,) = render(load_cell(cell_path), ["abb"])
    proc = rapidchecker(f.text, tmp_path / "hostile.mod")
    assert proc.returncode == 0, proc.stdout + proc.stderr


def test_rapidchecker_lacks_local_routines(tmp_path):
    """The one construct the check removes: rapidchecker rejects a LOCAL PROC and accepts LOCAL data."""
    module = 'MODULE m\n  LOCAL CONST num A := 1;\n\n  LOCAL PROC p()\n    TPWrite "x";\n  ENDPROC\nENDMODULE\n'
    raw = rapidchecker_raw(module, tmp_path / "local.mod")
    assert raw.returncode != 0 and "LOCAL" in raw.stdout
    assert rapidchecker(module, tmp_path / "local.mod").returncode == 0


def test_rapidchecker_is_not_vacuous(tmp_path):
    (f,) = render(load_cell(), ["abb"])
    assert rapidchecker(f.text.replace("RETURN d;", "RETURN d", 1), tmp_path / "broken.mod").returncode != 0
