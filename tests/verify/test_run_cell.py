"""`codegen run FILES --cell CELL`: a program codegen did not write, run on the cell's arm among its solids."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
from click.testing import CliRunner

from codegen.cli import main
from codegen.model.cell import DEMO_CELL, load_cell

# the demo cell's UR10e from its home (axis 1 at 180 deg) swinging axis 1 to 90 deg: the tool's tip (200 mm, pointing
# down) passes (612, -366, 477) mm at 135 deg; a box there is met halfway, far from either end
HOME = [180.0, -90.0, 90.0, -90.0, -90.0, 0.0]


def cell_with(tmp_path: Path, solids: str) -> Path:
    text = Path(DEMO_CELL).read_text(encoding="utf-8")
    path = tmp_path / "cell.toml"
    path.write_text(text.replace("[cell.world]", "[cell.world]\n" + solids.rstrip("\n"), 1), encoding="utf-8")
    for name in Path(DEMO_CELL).parent.glob("agv_*.csv"):  # the cell's data files beside it
        (tmp_path / name.name).write_text(name.read_text(encoding="utf-8"), encoding="utf-8")
    return path


def script(tmp_path: Path, axis1_deg: float) -> Path:
    q = np.radians([axis1_deg, *HOME[1:]])
    path = tmp_path / "swing.script"
    path.write_text(
        "def swing():\n"
        "  set_tcp(p[0, 0, 0.2, 0, 0, 0])\n"
        f"  movej([{', '.join(f'{v:.6f}' for v in q)}])\n"
        "end\n",
        encoding="utf-8",
    )
    return path


BOX = 'solids.machine = { box = [100, 100, 100], pose = [612, -366, 500, 0, 0, 0] }\n'


def invoke(*args):
    return CliRunner().invoke(main, [str(a) for a in args])


def test_a_swing_through_a_machine_is_reported_with_its_move_link_and_solid(tmp_path):
    cell = cell_with(tmp_path, BOX)
    result = invoke("run", script(tmp_path, 90.0), "--cell", cell)
    assert result.exit_code == 1, result.output
    assert "CLEARANCE: swing.script:3: the joint move: the tool cuts" in result.output
    assert "into machine (clearance 20 mm)" in result.output


def test_a_clean_run_says_its_least_clearance(tmp_path):
    cell = cell_with(tmp_path, BOX)
    result = invoke("run", script(tmp_path, 160.0), "--cell", cell)  # stops short of the box
    assert result.exit_code == 0, result.output
    assert "clearance: least " in result.output and "the cell's clearance 20 mm" in result.output
    data = json.loads(invoke("run", script(tmp_path, 160.0), "--cell", cell, "--json").output)
    assert data["clearance"]["breach"] is None and data["clearance"]["least"]["distance_mm"] >= 20.0


def test_a_krl_program_through_the_floor_is_reported(tmp_path):
    """A hand-written KRL PTP that dips the KR 10's tool below a raised floor (mounting plane at 300 mm)."""
    cell = cell_with(tmp_path, "floor_z_mm = 300.0\n")
    assert load_cell(cell).world.floor_z_mm == 300.0
    src = tmp_path / "dip.src"
    src.write_text(
        "DEF dip()\n"
        "  $TOOL = {X 0, Y 0, Z 200, A 0, B 0, C 0}\n"
        "  $BASE = {X 0, Y 0, Z 0, A 0, B 0, C 0}\n"
        "  PTP {A1 0, A2 -90, A3 90, A4 0, A5 90, A6 30}\n"
        "  PTP {A1 0, A2 -30, A3 90, A4 0, A5 90, A6 30}\n"
        "END\n",
        encoding="utf-8",
    )
    result = invoke("run", src, "--cell", cell)
    assert result.exit_code == 1, result.output
    assert "CLEARANCE: dip.src:5: the joint move:" in result.output and "floor" in result.output


def test_cell_and_robot_together_are_refused(tmp_path):
    cell = cell_with(tmp_path, BOX)
    result = invoke("run", script(tmp_path, 90.0), "--cell", cell, "--robot", "UR10e")
    assert result.exit_code == 2 and "--robot and --cell" in result.output
