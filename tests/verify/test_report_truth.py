"""verify's report tells the truth about a program given to it: its files paired with the generated ones by name,
the configuration change named by its joint, no Python None in a message, the least joint margin with its move and
case."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from click.testing import CliRunner

from codegen.cli import main
from codegen.dialects.core.files import SourceFile
from codegen.model.cell import EXAMPLES_DIR
from codegen.model.robot import Margins
from codegen.robot.arms import find_arm
from codegen.robot.expect import ArmStats
from codegen.verify import checks
from codegen.verify.checks import Checker
from codegen.verify.edits import _changed_lines, _texts
from codegen.verify.plan import PlannedMove

GENERATED = Path(__file__).resolve().parents[2] / "generated"
SRC, DAT, COUNT = "DEF PAL()\nEND\n", "DEFDAT PAL PUBLIC\nDECL INT N = 1\nENDDAT\n", "DEFDAT PAL_COUNT\nENDDAT\n"


def _program(*files: tuple[str, str]):
    return SimpleNamespace(files=[SourceFile(name, text) for name, text in files])


def test_data_files_as_generated_pair_by_name_not_by_suffix():
    """With two .dat files the notes crossed them: EDIT pal.dat:3 changed ... for a .dat byte-identical."""
    generated = _program(("pal.src", SRC), ("pal.dat", DAT), ("pal_count.dat", COUNT))
    given = _program(("here/pal.src", SRC), ("here/pal_count.dat", COUNT), ("here/pal.dat", DAT))
    assert _changed_lines(given, generated) == []
    generated = _program(("pal.src", SRC), ("pal_count.dat", COUNT), ("pal.dat", DAT))
    given = _program(("pal.src", SRC), ("pal.dat", DAT), ("pal_count.dat", COUNT))
    assert _changed_lines(given, generated) == []


def test_a_renamed_program_pairs_its_data_files_alike_and_an_edit_is_named_in_its_file():
    generated = _program(("pal.src", SRC), ("pal.dat", DAT), ("pal_count.dat", COUNT))
    edited = DAT.replace("N = 1", "N = 2")
    given = _program(("mine.src", SRC), ("mine_count.dat", COUNT), ("mine.dat", edited))
    assert _changed_lines(given, generated) == ["EDIT mine.dat:2 changed: DECL INT N = 2"]


def test_several_rapid_modules_pair_by_name():
    main_mod, b_mod = "MODULE main\nENDMODULE\n", "MODULE b\nENDMODULE\n"
    a_mod = "MODULE a\nVAR num x := 1;\nENDMODULE\n"
    generated = _program(("main.mod", main_mod), ("a.mod", a_mod), ("b.mod", b_mod))
    given = _program(("main.mod", main_mod), ("b.mod", b_mod), ("a.mod", a_mod.replace(":= 1", ":= 3")))
    assert _changed_lines(given, generated) == ["EDIT a.mod:2 changed: VAR num x := 3;"]


def test_a_setting_not_set_is_said_so_never_none():
    """"approx C_DIS, expected None" reached the user."""
    assert checks._setting(None) == "not set"
    assert checks._setting(0.2) == "0.2" and checks._setting("C_DIS") == "C_DIS"


def test_the_configuration_change_names_the_joint_its_values_and_the_way_out(tmp_path):
    """The message named no joint: axis 5 crossed 0."""
    program = tmp_path / "flip.script"
    program.write_text(
        "def prog():\n  movej([0, -1.57, 1.57, -1.57, 0.2, 0])\n"
        "  p = get_forward_kin([0, -1.57, 1.57, -1.57, -0.2, 0])\n  movel(p)\nend\n",
        encoding="utf-8",
    )
    result = CliRunner().invoke(main, ["run", str(program), "--robot", "UR5e"])
    assert result.exit_code == 1, result.output
    assert "flip.script:4:3: a linear move would change the arm's configuration: axis 5 passes its singular angle" in (
        result.stderr
    )
    assert "(the wrist flips: from 11.5 to -11.5 deg)" in result.stderr
    assert "Reach the pose with a joint move first" in result.stderr


def test_the_least_joint_margin_names_its_axis_move_and_case():
    """verify said 0.3 deg to a joint limit without saying which move or scenario."""
    arm = find_arm("UR5e")
    cell = SimpleNamespace(robot=SimpleNamespace(arms={"ur": arm}, margins=Margins(5.0, 5.0)))

    def moves(*joints):
        return [SimpleNamespace(joints=q, line=10 + i) for i, q in enumerate(joints)]

    first, second = ArmStats(), ArmStats()
    first.add(cell, "ur", moves([0, -90, 90, -90, 90, 0], [0, -90, 300, -90, 90, 0]), lambda: "station 1 nominal")
    asked = []
    late = moves([0, 0, 0, 0, 0, 0], [10, 0, 0, 0, 0, -355])
    second.add(cell, "ur", late, lambda: asked.append(1) or "station 2 late")
    second.add(cell, "ur", moves([0, 0, 0, 0, 0, 0]), lambda: asked.append(2) or "not the least")
    assert first.joint_margin_at == "axis 3 at 300.0 deg, move 2 (line 11), station 1 nominal"
    first.merge(second)
    assert first.joint_margin_deg == 5.0 and asked == [1]
    assert first.summary()["joint_margin_at"] == "axis 6 at -355.0 deg, move 2 (line 11), station 2 late"


def test_a_text_changed_alone_on_its_line_is_a_rename():
    generated = _program(
        ("m.mod", 'MODULE m\nTPWrite "no part";\nTPWrite "a ""b""" + s;\nx := 1; TPWrite "same";\nENDMODULE\n')
    )
    given = _program(
        ("m.mod", 'MODULE m\nTPWrite "kein Teil";\nTPWrite "ein ""b""" + s;\nx := 2; TPWrite "gleich";\nENDMODULE\n')
    )
    # the third line changes code too: its text is not a translation
    assert _texts(given, generated) == {"no part": "kein Teil", 'a ""b""': 'ein ""b""'}
    swapped = _program(("m.mod", 'MODULE m\nTPWrite "same";\nTPWrite "a ""b""" + s;\nx := 1; TPWrite "same";\n'))
    assert _texts(swapped, generated) == {}  # another stop's text: the stop's cause no longer told


def test_a_stop_whose_text_was_translated_is_the_same_stop():
    """A translated operator message failed verify as a mismatch."""
    expected = SimpleNamespace(halt="pallet 1 is full: swap it")
    trace = SimpleNamespace(halted=True, halt_message="Palette 1 voll: wechseln", moves=[])
    assert Checker._stop(expected, trace) is not None
    renames = {"pallet ": "Palette ", " is full: swap it": " voll: wechseln"}
    assert Checker._stop(expected, trace, renames) is None
    other = SimpleNamespace(halted=True, halt_message="Palette 1: kein Platz", moves=[])
    assert "expected 'pallet 1 is full: swap it'" in Checker._stop(expected, other, renames)


@pytest.mark.slow  # a whole verify of the pallet program, and its generated twin rendered
def test_verify_reports_a_translated_stop_message_as_an_edit(tmp_path):
    for path in (GENERATED / "eur_pallet" / "kuka").glob("pal_eur*"):
        (tmp_path / path.name).write_text(path.read_text(encoding="utf-8"), encoding="utf-8")
    src = tmp_path / "pal_eur.src"
    old = "pallet eur is full: swap it, then reset its counters from the PLC"
    src.write_text(src.read_text(encoding="utf-8").replace(old, "Palette eur voll"), encoding="utf-8")
    files = [str(tmp_path / n) for n in ("pal_eur.src", "pal_eur.dat", "pal_eur_count.dat")]
    args = ["verify", str(EXAMPLES_DIR / "pallets" / "eur_pallet.toml"), *files, "--target", "kuka", "--cases", "5"]
    result = CliRunner().invoke(main, [*args, "--jobs", "1"])
    assert result.exit_code == 0, result.output
    assert f"EDIT effect: shows 'Palette eur voll' where the generated program shows {old!r}" in result.output
    assert "MISMATCH" not in result.output


@pytest.mark.parametrize(
    ("target", "change", "stop_note"),
    [
        ("ur", {"v": 0.08}, False),  # a speed edit is no blend: the stop note misled
        ("ur", {"r": 0.002}, True),
        ("kuka", {"vel_cp": 0.08}, False),
        ("kuka", {"approx": "C_DIS", "cdis": 2.0}, True),
    ],
)
def test_the_exact_stop_note_comes_with_a_blend_only(target, change, stop_note):
    checker = Checker.__new__(Checker)
    checker.target, checker.own_tool = checks.get_target(target), False
    checker.pos_tol = checker.rot_tol = 1.0
    planned = PlannedMove(name="die", kind="linear", exact=True, speed_mm_s=50.0, zone_mm=5.0)
    wanted = checks.move_settings(target, "linear", True, False, 50.0, 5.0, None)
    trace = SimpleNamespace(moves=[SimpleNamespace(line=7, kind="linear", settings={**wanted, **change})])
    message, _pos, _rot = checker._moves(SimpleNamespace(moves=[planned]), trace)
    assert message.startswith("move 1 (die, line 7): ")
    assert ("must stop exactly" in message) is stop_note


def test_the_report_counts_one_program_in_the_singular():
    """ "cell press_shop: 1 programs" read as a slip."""
    from codegen.verify.report import Report

    assert Report("press_shop", [object()], 0, 0).header() == "cell press_shop: 1 program (seed 0)"
    assert Report("press_shop", [object(), object()], 3, 0).header() == "cell press_shop: 2 programs (seed 3)"


def _moves(*poses):
    """Trace moves at given (x, y, z mm, turn about z deg), None for a joint position, lines from 10."""
    out = []
    for i, pose in enumerate(poses):
        if pose is None:
            out.append(SimpleNamespace(tcp2base=None, line=10 + i))
            continue
        x, y, z, deg = pose
        c, s = np.cos(np.radians(deg)), np.sin(np.radians(deg))
        m = np.array([[c, -s, 0, x], [s, c, 0, y], [0, 0, 1, z], [0, 0, 0, 1.0]])
        out.append(SimpleNamespace(tcp2base=m, line=10 + i))
    return out


def test_a_moved_target_is_named_with_how_far_and_how_much_turned():
    from codegen.verify.edits import _poses

    generated = SimpleNamespace(moves=_moves(None, (600, 0, 300, 0), (600, 0, 200, 0), (650, 10, 200, 30)))
    given = SimpleNamespace(moves=_moves(None, (600, 0, 320, 0), (600, 0, 220, 0), (650, 10, 200, 31.5)))
    assert _poses(given, generated) == [
        "moves 2-3 (from line 11) 20.000 mm and 0.000 deg from the generated program's target",
        "move 4 (from line 13) 0.000 mm and 1.500 deg from the generated program's target",
    ]
    # within float32's tolerance (0.005 mm, 0.001 deg) a target is the same
    close = SimpleNamespace(moves=_moves(None, (600.004, 0, 300, 0), (600, 0, 200, 0.0009), (650, 10, 200, 30)))
    assert _poses(close, generated) == []


def test_one_problem_met_in_many_cases_is_one_mismatch_line_whatever_float32_adds():
    """A target edited 20 mm away: every case's error is 20 mm but for float32's millionths; one line, the rest
    counted. A problem a thousandth of a mm apart or more is another line."""
    from codegen.verify.report import Row, alike_key

    row = Row("station", "ur", "p", ["p.script"])
    for i, (pos, rot) in enumerate([(19.999993, 0.000001), (19.999993, 0.000003), (19.999994, 0.000011)]):
        problem = f"move 3 (vise_above, line 208): position error {pos:.6f} mm, orientation error {rot:.6f} deg"
        row.mismatch(f"random station 7 reading ({i}): {problem}", alike_key(problem))
    other = "move 3 (vise_above, line 208): position error 20.004000 mm, orientation error 0.000000 deg"
    row.mismatch(f"random station 7 reading (9): {other}", alike_key(other))
    assert len(row.first_mismatches) == 2 and list(row.alike.values()) == [2, 0]
    assert row.first_mismatches[0].endswith("position error 19.999993 mm, orientation error 0.000001 deg")
    assert alike_key("error -0.0004 mm, 12.3456789 deg, line 208") == "error 0.000 mm, 12.346 deg, line 208"
