"""The posture the pallet, conveyor and laser kinds work in: a pallet whose controller's own posture from the home does
not clear is worked in another branch, named in each target's form and held by verify; a belt or laser cell whose
posture does not clear is refused naming the move, the solid, the home and the fix."""

from __future__ import annotations

import numpy as np
import pytest
from click.testing import CliRunner
from support.cells import EXAMPLES

from codegen.cli import main
from codegen.generate import GenerateError, check_clearance, generate
from codegen.kinds.pallet import program as pallet_program
from codegen.kinds.pallet.plan import configurations, posture_note
from codegen.kinds.pallet.reach import plan
from codegen.kinds.pallet.scene import pallet_paths
from codegen.model.cell import load_cell
from codegen.render import render
from codegen.verify.engine import Options, verify_cell
from codegen.world.proof import ClearanceError, prove

ROBOT = "[cell.robot]               # a small six-axis arm per controller (source 004 names none); dtrans has no arm "
TOOL = "tcp = [0.0, 0.0, 120.0, 0.0, 0.0, 0.0]"
# The cells: testmat (each proven on one target), where the posture the controller takes from the home does not clear.
# UR5e: the home with the wrist turned over (axis 4 at +90, axis 5 at +90): from there the solution nearest the home
# reaches down with the elbow under the work, the upper arm through the floor. KUKA and ABB: the analytic branches that
# reach testmat differ only in the wrist (axis 5's sign), whose end poses are the same; a 300 mm tool and a 20 mm cube
# ("beam") where the tool passes on the joint move from the home to above Q with the wrist as the home has it (the
# point found by the forward kinematics of that move: more than 100 mm from every body of the other wrist's cycle).
CASES = {
    "ur": ("home = { ur = [0.0, -90.0, 90.0, 90.0, 90.0, 0.0] }", TOOL, None),
    "kuka": ("", "tcp = [0.0, 0.0, 300.0, 0.0, 0.0, 0.0]", (528.0, 61.0, 421.0)),
    "abb": ("", "tcp = [0.0, 0.0, 300.0, 0.0, 0.0, 0.0]", (550.0, 83.0, 388.0)),
}


def _testmat(target: str, home: str = "") -> str:
    extra, tcp, beam = CASES[target]
    text = EXAMPLES["testmat_pallet"].read_text(encoding="utf-8")
    text = text.replace(ROBOT + "model", "[cell.robot]\n" + (home or extra), 1).replace(TOOL, tcp, 1)
    if beam is not None:
        x, y, z = beam
        solid = f"beam = {{ box = [20.0, 20.0, 20.0], pose = [{x}, {y}, {z}, 0.0, 0.0, 0.0] }}"
        text = text.replace("[cell.tool]", f"[cell.world]\nsolids = {{ {solid} }}\n\n[cell.tool]", 1)
    return text


def _cell(tmp_path, target: str, home: str = ""):
    path = tmp_path / f"testmat_{target}.toml"
    path.write_text(_testmat(target, home), encoding="utf-8")
    return load_cell(path)


def _first_joints(cell, target: str, named) -> np.ndarray:
    pallets = cell.sections["pallet"]
    return pallet_paths(cell, pallets, pallets[0], target, named)[0].moves[0].joints


@pytest.mark.parametrize("target", ["ur", "kuka", "abb"])
def test_a_pallet_whose_nearest_home_posture_collides_is_worked_in_another_branch(tmp_path, target):
    """The controller's own posture from the home is refused by the clearance proof (the floor on the UR, the beam on
    KUKA and ABB); generate chooses another analytic branch for the whole cycle, says so naming the home, and the
    program names it in the target's own form: the configurations it prints differ from those of the controller's
    own posture."""
    cell = _cell(tmp_path, target)
    pallet = cell.sections["pallet"][0]
    natural = plan(cell, pallet, target)
    with pytest.raises(ClearanceError) as caught:
        prove(cell, pallet_paths(cell, cell.sections["pallet"], pallet, target, natural))
    hit = "the floor" if target == "ur" else "the solid 'beam'"
    assert hit in str(caught.value)
    assert check_clearance(cell, [target])  # the chosen posture clears every path generate proves
    chosen = configurations(cell, pallet, target)
    note = posture_note(cell, pallet, target)
    assert note.startswith("posture chosen to clear the cell: every joint move in the arm's configuration ")
    assert f"the configuration nearest the home [cell.robot.home] {target} = [" in note and "does not clear" in note
    first, own = _first_joints(cell, target, chosen), _first_joints(cell, target, natural)
    arm = cell.robot.arms[target]
    np.testing.assert_allclose(arm.kin.fk(first), arm.kin.fk(own), atol=1e-6)  # the same pose above Q
    assert np.max(np.abs(first - own)) > 30.0  # in another configuration
    ours = {f.relpath: f.text for f in render(cell, [target])}
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(pallet_program, "configurations", lambda c, p, t: plan(c, p, t))
        theirs = {f.relpath: f.text for f in render(_cell(tmp_path, target), [target])}
    assert ours.keys() == theirs.keys() and ours != theirs


def _steered_back(tmp_path, target: str) -> tuple[list[str], list[str], object]:
    """The generated program, and the same program written with the controller's own configurations (the posture
    steered back to the one nearest the home), each in its own folder."""
    cell = _cell(tmp_path, target)
    written, _, envelopes = generate(cell, [target], tmp_path / "chosen")
    assert any("posture chosen to clear the cell" in e.text() for e in envelopes)
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(pallet_program, "configurations", lambda c, p, t: plan(c, p, t))
        files = render(_cell(tmp_path, target), [target])
    steered = []
    for f in files:
        path = tmp_path / "steered" / f.relpath
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(f.text, encoding="utf-8")
        steered.append(str(path))
    programs = [str(p) for p in written if "node" not in p.name]
    return programs, [p for p in steered if "node" not in p], cell


@pytest.mark.slow
@pytest.mark.parametrize("target", ["ur", "kuka", "abb"])
def test_verify_holds_the_pallet_program_to_the_chosen_posture(tmp_path, target):
    """The program generated in the chosen posture passes verify; the same program naming the controller's own
    configurations (steered back to the posture nearest the home) fails it."""
    chosen, steered, cell = _steered_back(tmp_path, target)
    options = Options(cases=2, seed=5, jobs=1, sweeps=False)
    assert verify_cell(cell, chosen, (target,), options).ok
    report = verify_cell(cell, steered, (target,), options)
    assert not report.ok


def test_a_pallet_where_no_posture_clears_is_refused_naming_the_home_and_the_configuration_tried(tmp_path):
    """The UR5e's home folded down (axis 2 at -150, axis 3 at -90): no branch clears the floor; the refusal names the
    move, the floor, the home in use and the configurations tried."""
    text = _testmat("ur", "home = { ur = [180.0, -150.0, -90.0, -90.0, -90.0, 0.0] }")
    path = tmp_path / "testmat_folded.toml"
    path.write_text(text, encoding="utf-8")
    out = tmp_path / "out"
    result = CliRunner().invoke(main, ["generate", str(path), "--target", "ur", "--out", str(out)])
    assert result.exit_code == 2 and "Traceback" not in result.output and not out.exists(), result.output
    said = " ".join(result.output.split())
    assert "pallet 'testmat' layer 1 box 1 above Q (ur, UR5e): the upper_arm dips below the floor" in said
    assert "the configuration tried (the controller's own from the home, else each analytic branch for the " in said
    assert "from the home [cell.robot.home] ur = [180, -150, -90, -90, -90, 0]" in said


@pytest.mark.parametrize(
    ("example", "move", "solid"),
    [
        ("belt_pick", "conveyor: the part at x -50, y -150, its top 40 mm over the belt: above the part", "'belt'"),
        ("laser_tcp", "laser station: the safe pose", "'sensor X'"),
    ],
)
def test_a_belt_or_laser_cell_whose_posture_does_not_clear_is_refused_naming_the_move_the_solid_and_the_fix(
    tmp_path, example, move, solid
):
    """Their programs name no configuration: from the catalogue's home (facing -x) the solution nearest the home reaches
    the work with the elbow under it, through the belt or the sensor's column: refused, exit 2, nothing written, naming
    the move, the solid, the home and the fix (another home: the one turned half a turn about axis 1 clears)."""
    text = EXAMPLES[example].read_text(encoding="utf-8")
    assert "home = { ur = [180.0, -90.0, 90.0, -90.0, -90.0, 0.0] }\n" in text
    path = tmp_path / f"{example}.toml"
    path.write_text(text.replace("home = { ur = [180.0, -90.0, 90.0, -90.0, -90.0, 0.0] }\n", ""), encoding="utf-8")
    out = tmp_path / "out"
    result = CliRunner().invoke(main, ["generate", str(path), "--target", "ur", "--out", str(out)])
    assert result.exit_code == 2 and "Traceback" not in result.output and not out.exists(), result.output
    said = " ".join(result.output.split())
    assert f"{move} (ur, UR10e): the " in said and f"the solid {solid}" in said
    assert "another home than [cell.robot.home] ur = [0, -90, 90, -90, -90, 0]" in said
    assert "(the program names none: the controller takes the solution nearest the home; another home gives" in said
    assert "from the home turned half a turn about axis 1, ur = [-180, -90, 90, -90, -90, 0], every move clears" in said
    with pytest.raises(GenerateError):
        check_clearance(load_cell(path), ["ur"])
