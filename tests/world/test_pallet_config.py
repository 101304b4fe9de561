"""A pallet's configuration named by the cell ([pallet.config]): kept as given without a search and named by the
program in the target's own form where it clears; refused naming the key where it does not clear or does not reach; a
bad value refused naming the key and its line."""

from __future__ import annotations

import math
import re

import pytest
from click.testing import CliRunner
from world.test_posture_kinds import _testmat

from codegen.cli import main
from codegen.generate import check_clearance, generate
from codegen.kinds.pallet import posture
from codegen.kinds.pallet import program as pallet_program
from codegen.kinds.pallet.plan import configurations, posture_note
from codegen.kinds.pallet.reach import plan
from codegen.model.cell import load_cell
from codegen.render import render
from codegen.verify.engine import Options, verify_cell

# The testmat cells of test_posture_kinds (the controller's own posture from the home does not clear: the floor on the
# UR5e, the beam on KUKA and ABB). CLEARS: the configuration above Q of the branch generate's search keeps there (read
# off its report and programs, UR's joints rounded to 0.001 deg); BLOCKED: the controller's own from the home.
CLEARS = {
    "ur": "ur = [-164.897, -56.873, 90.786, 236.087, -90, -74.897]",
    "kuka": "kuka = { s = 6, t = 51 }",
    "abb": "abb = [0, 2, 0, 1]",
}
BLOCKED = {
    "ur": "ur = [38.027, -209.253, 90.786, 208.467, 90, -51.973]",
    "kuka": "kuka = { s = 2, t = 3 }",
    "abb": "abb = [0, 0, -2, 0]",
}
PROGRAM = {"ur": "pal_testmat.script", "kuka": "pal_testmat.dat", "abb": "pal_testmat.mod"}
# each program's line that names the configuration above Q (UR: qnear in rad)
NAMED = {
    "ur": r"PAL_ABOVE_QNEAR = \[([^\]]*)\]",
    "kuka": r"DECL E6POS PAL_ABOVE=\{[^}]*,S 6,T 51,",
    "abb": r"robtarget stack_q := \[\[[^\]]*\], \[[^\]]*\], \[0, 2, 0, 1\],",
}


def _named_text(target: str, line: str) -> str:
    text = _testmat(target)
    assert text.count("\n[pallet.io") == 1
    return text.replace("\n[pallet.io", f"\n[pallet.config]\n{line}\n\n[pallet.io", 1)


def _write(folder, name: str, text: str):
    folder.mkdir(exist_ok=True)
    path = folder / name
    path.write_text(text, encoding="utf-8")
    return path


def _programs(cell, target: str) -> dict:
    """The rendered files without their header's hash of the cell file (the two cells' files differ by the key)."""
    return {f.relpath: re.sub(r"sha256 [0-9a-f]{64}", "", f.text) for f in render(cell, [target])}


# KUKA's configuration above Q as joints (to 0.01 deg) instead of S and T: the same branch, the same program
AS_JOINTS = "kuka = { joints = [-26.57, -45.62, 89.37, 180, -46.24, -26.57] }"


@pytest.mark.parametrize(
    ("target", "line"), [("ur", CLEARS["ur"]), ("kuka", CLEARS["kuka"]), ("abb", CLEARS["abb"]), ("kuka", AS_JOINTS)]
)
def test_a_named_configuration_that_clears_is_kept_and_named_by_the_program(tmp_path, target, line, monkeypatch):
    """The cell names the configuration generate's search would keep: it is taken as given (no search: the candidates
    are never asked for), nothing is reported as chosen, the programs are those of the search, and each names it in
    its own form (UR's qnear the named joints, KUKA S and T, ABB confdata)."""
    searched = _programs(load_cell(_write(tmp_path / "searched", "testmat.toml", _testmat(target))), target)

    def no_search(*args):
        raise AssertionError("a configuration the cell names is not searched for")

    monkeypatch.setattr(posture, "_candidates", no_search)
    cell = load_cell(_write(tmp_path / "named", "testmat.toml", _named_text(target, line)))
    pallet = cell.sections["pallet"][0]
    named = configurations(cell, pallet, target)
    assert named.source == f"[pallet.config] {line} of pallet 'testmat'"
    assert posture_note(cell, pallet, target) == ""
    assert check_clearance(cell, [target])
    ours = _programs(cell, target)
    assert ours == searched
    script = ours[f"testmat_pallet/{target}/{PROGRAM[target]}"]
    found = re.search(NAMED[target], script)
    assert found, NAMED[target]
    if target == "ur":
        given = [float(v) for v in CLEARS["ur"].split("[")[1].rstrip("]").split(",")]
        printed = [float(v) for v in found.group(1).split(",")]
        assert max(abs(p - math.radians(g)) for p, g in zip(printed, given, strict=True)) < 5e-5


@pytest.mark.parametrize("target", ["ur", "kuka", "abb"])
def test_a_named_configuration_that_does_not_clear_is_refused_naming_the_key(tmp_path, target):
    """The controller's own configuration from the home, named by the cell: generate refuses (exit 2, nothing
    written), naming the move, what it hits and the key."""
    path = _write(tmp_path, "blocked.toml", _named_text(target, BLOCKED[target]))
    out = tmp_path / "out"
    result = CliRunner().invoke(main, ["generate", str(path), "--target", target, "--out", str(out)])
    assert result.exit_code == 2 and "Traceback" not in result.output and not out.exists(), result.output
    said = " ".join(result.output.split())
    hit = "dips below the floor" if target == "ur" else "touches the solid 'beam'"
    assert f"pallet 'testmat' layer 1 box 1 above Q ({target}, " in said and hit in said
    assert f"[pallet.config] {BLOCKED[target]} of pallet 'testmat'" in said


def test_a_named_configuration_the_arm_cannot_take_above_q_is_refused_naming_the_key(tmp_path):
    """ABB confdata with axis 1 in its third quadrant (180 to 270 deg): no solution above Q has it."""
    path = _write(tmp_path, "unreached.toml", _named_text("abb", "abb = [2, 0, 0, 0]"))
    out = tmp_path / "out"
    result = CliRunner().invoke(main, ["generate", str(path), "--target", "abb", "--out", str(out)])
    assert result.exit_code == 2 and "Traceback" not in result.output and not out.exists(), result.output
    said = " ".join(result.output.split())
    assert (
        "[pallet.config] abb = [2, 0, 0, 0] of pallet 'testmat': the arm takes no solution in this configuration "
        "above Q" in said
    )


@pytest.mark.parametrize(
    ("target", "line", "kept"),
    [
        ("ur", "ur = [195.103, -56.873, 90.786, 236.087, -90, -74.897]", "[-164.897, -56.873, "),
        ("kuka", "kuka = { s = 6, t = 19 }", "{ s = 6, t = 51 }"),
    ],
)
def test_a_named_configuration_a_turn_from_the_cycles_is_refused_naming_the_one_to_give(tmp_path, target, line, kept):
    """Axis 1 (UR) or axis 6 (KUKA, Turn bit 5) a turn from where the cycle in that branch comes above Q from the home:
    the program could not name it; the refusal names the key and the configuration the cycle takes there."""
    path = _write(tmp_path, "turned.toml", _named_text(target, line))
    out = tmp_path / "out"
    result = CliRunner().invoke(main, ["generate", str(path), "--target", target, "--out", str(out)])
    assert result.exit_code == 2 and "Traceback" not in result.output and not out.exists(), result.output
    said = " ".join(result.output.split())
    assert f"[pallet.config] {line} of pallet 'testmat': the cycle worked in this configuration's branch comes " in said
    assert f"above Q from the home in {kept}" in said and "name that one" in said


@pytest.mark.parametrize(
    ("target", "line", "key", "said"),
    [
        ("ur", "ur = [1.0, 2.0]", "pallet[0].config.ur", "expected 6 numbers, got 2"),
        ("ur", "ur = [400.0, 0.0, 0.0, 0.0, 0.0, 0.0]", "pallet[0].config.ur[0]", "axis 1 at 400 deg is outside"),
        ("kuka", "kuka = [6, 51]", "pallet[0].config.kuka", "expected { s = status, t = turn } or { joints = [...] }"),
        ("kuka", "kuka = { s = 8, t = 51 }", "pallet[0].config.kuka.s", "expected a whole number in 0..7"),
        ("abb", "abb = [0, 2, 0, 9]", "pallet[0].config.abb[3]", "expected a whole number in -8..7"),
        ("ur", "dtrans = [0]", "pallet[0].config.dtrans", "no arm for this target in [cell.robot]"),
    ],
)
def test_a_bad_configuration_is_refused_naming_the_key_and_its_line(tmp_path, target, line, key, said):
    text = _named_text(target, line)
    number = text.splitlines().index(line) + 1
    path = _write(tmp_path, "bad.toml", text)
    out = tmp_path / "out"
    result = CliRunner().invoke(main, ["generate", str(path), "--target", target, "--out", str(out)])
    assert result.exit_code == 2 and "Traceback" not in result.output and not out.exists(), result.output
    assert f"line {number}: {key}: {said}" in result.output


@pytest.mark.slow
def test_verify_holds_the_program_to_the_named_configuration(tmp_path):
    """verify plans the cell's named configuration as generate does: the program generated from it passes; the same
    program written with the controller's own configurations from the home fails."""
    cell = load_cell(_write(tmp_path, "named.toml", _named_text("kuka", CLEARS["kuka"])))
    written, _, _ = generate(cell, ["kuka"], tmp_path / "named")
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(pallet_program, "configurations", lambda c, p, t: plan(c, p, t))
        files = render(cell, ["kuka"])
    steered = []
    for f in files:
        path = tmp_path / "steered" / f.relpath
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(f.text, encoding="utf-8")
        steered.append(str(path))
    options = Options(cases=2, seed=5, jobs=1, sweeps=False)
    assert verify_cell(cell, [str(p) for p in written], ("kuka",), options).ok
    assert not verify_cell(cell, steered, ("kuka",), options).ok
