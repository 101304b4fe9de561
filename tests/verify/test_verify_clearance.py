"""verify sweeps the demo's traces among the cell's solids: a hand edit that swings the arm into a solid, and a zone
widened so that its corner cuts into one, each fail verify naming the move, the body and the solid."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from codegen.model.cell import DEMO_CELL, load_cell
from codegen.render import render
from codegen.verify.engine import Options, verify_cell

GENERATED = Path(__file__).resolve().parents[2] / "generated" / "agv_machine_tending" / "ur"
PROGRAM = "agv_machine_tending.script"
FAST = Options(cases=1, jobs=1, sweeps=False, scenarios=frozenset({"random"}))
# a post in the inside of station 1's corner at the done part's tray ((520, -480, 370) mm: in from the
# chuck, then straight down): 30 mm from either straight line's tool (radius 25), 25 mm beside the next line along
# the tray
POST = 'solids.post = { box = [60, 40, 100], pose = [534.0, -394.8, 290.0, 70.66, 0, 0] }\n'


PART = "[station.part]                    # the part the gripper carries: 60 x 60 x 80 mm under the TCP\n"


def cell_with(tmp_path: Path, world: str, part: bool = True):
    """The demo cell with `world` added to [cell.world]; part False: no station declares the part it carries (the
    tool alone is swept where the gripper holds one)."""
    text = Path(DEMO_CELL).read_text(encoding="utf-8")
    if not part:  # every [station.part] table with its keys
        text, removed = re.subn(re.escape(PART) + r"(?:[a-z_]+ = [^\n]*\n)+", "", text)
        assert removed
    path = tmp_path / "cell" / "agv_machine_tending.toml"
    path.parent.mkdir()
    path.write_text(text.replace("[cell.world]", "[cell.world]\n" + world.rstrip("\n"), 1), encoding="utf-8")
    for name in Path(DEMO_CELL).parent.glob("agv_*.csv"):  # the cell's data files beside it
        (path.parent / name.name).write_text(name.read_text(encoding="utf-8"), encoding="utf-8")
    return load_cell(path)


def rendered(tmp_path: Path, cell) -> Path:
    """The UR program generated from `cell` (a cell without parts loads the tool alone: not the bundled program)."""
    text = next(f.text for f in render(cell, ["ur"]) if f.relpath.endswith("/" + PROGRAM))
    path = tmp_path / "rendered" / PROGRAM
    path.parent.mkdir()
    path.write_text(text, encoding="utf-8")
    return path


def edited(tmp_path: Path, old: str, new: str, source: Path = GENERATED / PROGRAM) -> Path:
    text = source.read_text(encoding="utf-8")
    assert text.count(old) == 1
    path = tmp_path / PROGRAM
    path.write_text(text.replace(old, new), encoding="utf-8")
    return path


def line_of(text: str, source: Path = GENERATED / PROGRAM) -> int:
    """The line of the generated program that holds `text` (one line, once)."""
    lines = source.read_text(encoding="utf-8").splitlines()
    return lines.index(text.rstrip("\n")) + 1


def problems(cell, path: Path) -> list[str]:
    report = verify_cell(cell, [path], ("ur",), FAST)
    (row,) = report.rows
    assert row.clearance_traces == row.cases  # every random case of the fast run is swept
    return row.first_mismatches


CORNER = "    movel(p1_tray_done_above, a=1.2, v=0.2500, r=0.0100)\n"


def test_the_generated_program_clears_the_post_with_the_tool(tmp_path):
    cell = cell_with(tmp_path, POST, part=False)
    report = verify_cell(cell, [rendered(tmp_path, cell)], ("ur",), FAST)
    (row,) = report.rows
    assert row.mismatches == 0, row.first_mismatches
    assert row.clearance.distance >= 20.0


def test_the_part_carried_past_the_post_fails_naming_the_part(tmp_path):
    """The same post with the part declared: the part (60 mm wide, 80 mm under the TCP) that the gripper carries
    from the chuck down onto the tray passes the post within the clearance, where the tool alone keeps it."""
    cell = cell_with(tmp_path, POST)
    found = problems(cell, GENERATED / PROGRAM)
    assert found and all(": the linear move: the part cuts " in p and "into post (clearance 20 mm)" in p for p in found)


def test_a_zone_widened_into_the_post_fails_for_its_corner(tmp_path):
    cell = cell_with(tmp_path, POST, part=False)
    program = rendered(tmp_path, cell)
    found = problems(cell, edited(tmp_path, CORNER, CORNER.replace("r=0.0100", "r=0.1500"), program))
    line = line_of(CORNER, program)
    assert found and all(f"clearance: {PROGRAM}:{line}: the blend's corner (150 mm zone): the tool" in p for p in found)
    assert all("post (clearance 20 mm)" in p for p in found)


@pytest.mark.parametrize("target_line", ["    movel(p1_tray_done_up, a=1.2, v=0.0500, r=0.0100)\n"])
def test_a_hand_edit_swinging_the_arm_into_the_floor_fails_for_it(tmp_path, target_line):
    """The arm's way up from the tray edited into a joint move to a posture that dips the tool into the floor."""
    cell = cell_with(tmp_path, "floor_z_mm = 0.0\n")
    dip = "    movej([2.0, -0.3, 1.9, -1.6, -1.5708, 0.0], a=1.2, v=0.25)\n"
    found = problems(cell, edited(tmp_path, target_line, dip + target_line))
    line = line_of(target_line)  # the dip's line: the one the way up had
    assert found and all(f"clearance: {PROGRAM}:{line}: the joint move: the " in p and "floor" in p for p in found)


def test_a_module_rendered_from_the_cell_is_named_by_its_file():
    """verify without program files sweeps the programs it renders from the cell (named <fresh>/... inside): a RAPID
    move's place reads as the module's file and line, as a file's given on the command line does."""
    report = verify_cell(load_cell(DEMO_CELL), [], ("abb",), FAST)
    (row,) = report.rows
    assert row.clearance is not None and row.clearance.where.startswith("agv_machine_tending.mod:"), row.clearance.where
