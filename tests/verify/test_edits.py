"""verify of a hand-edited demo program names each edit (the line and its text) and what it changes in a run."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from codegen.kinds.station.section import stations_of
from codegen.model.cell import EXAMPLES_DIR, load_cell
from codegen.verify.engine import Options, verify_cell

DEMO = EXAMPLES_DIR / "agv_machine_tending.toml"
GENERATED = Path(__file__).resolve().parents[2] / "generated" / "agv_machine_tending"
FILES = {
    "abb": "abb/agv_machine_tending.mod",
    "ur": "ur/agv_machine_tending.script",
    "kuka": "kuka/agv_machine_tending.src",
}
# the line after which each edit goes: station 1's move to the chuck (its work pose), in each language
AFTER = {"abb": "MoveL vis_apply(corr, p1_chuck)", "ur": "movel(pose_trans(corr, p1_chuck)", "kuka": "P1_CHUCK"}
SHIFTS = frozenset({"random", "zero_shift", "inside_shift_limit"})  # cases that reach the work pose
FAST = Options(cases=1, jobs=1, sweeps=False, scenarios=frozenset({"random"}))


@pytest.fixture(scope="module")
def cell():
    return load_cell(DEMO)


def work_move(cell) -> int:
    """The number of station 1's move to its work pose in a run: the home move, then its taught poses (the last)."""
    return 1 + len(stations_of(cell)[0].poses)


def edited(tmp_path: Path, target: str, text: str, before: bool = False) -> tuple[Path, int]:
    """The demo's program for the target with one line added after (or before) station 1's move to the chuck;
    the file (under its own name, with its data file) and the added line's number."""
    source = GENERATED / FILES[target]
    lines = source.read_text().splitlines()
    at = next(
        i for i, line in enumerate(lines) if AFTER[target] in line and not line.lstrip().startswith(("TARGET", ";"))
    )
    if target == "kuka":  # the KRL motion to the chuck is the LIN after the TARGET line that names it
        at = next(i for i in range(at, len(lines)) if lines[i].lstrip().startswith("LIN"))
    at = at if before else at + 1
    lines.insert(at, "    " + text)
    path = tmp_path / source.name
    path.write_text("\n".join(lines) + "\n")
    for companion in source.parent.glob(source.stem + ".*"):
        if companion != source:
            (tmp_path / companion.name).write_text(companion.read_text())
    return path, at + 1


def verify(cell, path: Path, target: str, options: Options = FAST):
    report = verify_cell(cell, [path], (target,), options)
    (row,) = report.rows
    return report, row


@pytest.mark.parametrize(
    ("target", "text", "effect"),
    [
        ("abb", "WaitTime 0.5;", "reaches move {work_next} (line {n_next}) 0.50 s later than the generated program"),
        ("ur", "sleep(0.5)", "reaches move {work_next} (line {n_next}) 0.50 s later than the generated program"),
        ("kuka", "WAIT SEC 0.5", "0.50 s later than the generated program"),
        ("abb", 'TPWrite "at the chuck";', "writes 'at the chuck' (the generated program does not)"),
        ("abb", "Set doLamp;", "sets doLamp True after move {work} (line {n}); the generated program does not"),
    ],
)
def test_a_hand_edit_is_named_with_its_effect(cell, tmp_path, target, text, effect):
    path, n = edited(tmp_path, target, text)
    report, row = verify(cell, path, target)
    assert row.edits[0] == f"EDIT {path.name}:{n} added: {text}"
    effects = [e.removeprefix("EDIT effect: ") for e in row.edits[1:]]
    lines = path.read_text().splitlines()
    n_next = next(i + 1 for i in range(n, len(lines)) if lines[i].lstrip().startswith(("MoveL", "movel", "LIN")))
    work = work_move(cell)
    assert effect.format(n=n, n_next=n_next, work=work, work_next=work + 1) in " | ".join(effects), row.edits
    assert any(line.startswith(f"  EDIT {path.name}:{n}") for line in report.lines())
    assert report.as_json()["programs"][0]["edits"] == row.edits


def test_a_speed_change_is_named_on_the_moves_it_holds_for(cell, tmp_path):
    path, n = edited(tmp_path, "abb", "VelSet 50, 800;", before=True)
    _, row = verify(cell, path, "abb")
    assert row.edits[0] == f"EDIT {path.name}:{n} added: VelSet 50, 800;"
    settings = [e for e in row.edits if "velset {override 50, max 800}, generated not set" in e]
    work = work_move(cell)  # the setting holds for the work pose, the retreat and the way home
    assert settings and settings[0].startswith(f"EDIT effect: moves {work}-{work + 2} (from line {n + 1}) velset"), (
        row.edits
    )
    assert any("s longer than the generated program" in e for e in row.edits)
    assert row.mismatches == 0  # slower is allowed: verify judges the path, the edit is reported


def test_an_output_edit_fails_once_per_problem(cell, tmp_path):
    """The same difference in many cases is one MISMATCH line with their count."""
    path, n = edited(tmp_path, "abb", "Set doLamp;")
    report, row = verify(cell, path, "abb", Options(cases=1, jobs=1, sweeps=False, scenarios=SHIFTS))
    shown = [line for line in report.lines() if line.startswith("  MISMATCH")]
    assert row.mismatches > 1 and len(shown) == 1, shown
    assert f"output doLamp (line {n})" in shown[0]
    assert re.search(rf"\(and {row.mismatches - 1} more cases alike(; in [\w, ]+)?\)$", shown[0]), shown[0]


def test_a_program_as_generated_has_no_edits(cell, tmp_path):
    source = GENERATED / FILES["abb"]
    path = tmp_path / source.name
    path.write_text(source.read_text())
    _, row = verify(cell, path, "abb")
    assert row.edits == [] and row.mismatches == 0


def test_a_taught_pose_edited_in_the_program_is_named_with_how_far_it_moved(cell, tmp_path):
    """p1_chuck 10 mm higher (its z 0.3052 m made 0.3152 m): the move to it is 10 mm from the generated target."""
    source = GENERATED / FILES["ur"]
    old = "  p1_chuck = p[0.7385000, -0.1123000, 0.3052000,"
    text = source.read_text()
    assert old in text
    path = tmp_path / source.name
    path.write_text(text.replace(old, old.replace("0.3052000", "0.3152000"), 1))
    _, row = verify(cell, path, "ur")
    line = next(i + 1 for i, t in enumerate(path.read_text().splitlines()) if "movel(pose_trans(corr, p1_chuck)" in t)
    expected = f"EDIT effect: move {work_move(cell)} (from line {line}) 10.000 mm and 0.000 deg from the generated"
    assert any(e.startswith(expected) for e in row.edits), row.edits
