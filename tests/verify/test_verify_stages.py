"""verify sweeps what a case stands and carries, not only the world's fixed solids: a station's own machine, moved
by the case's reading as its poses are, and the pallet's stack as built at each point of the run, with the part the
gripper holds (its shape from the cell)."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from codegen.kinds.station.cases import Case
from codegen.kinds.station.mode import mode_of
from codegen.kinds.station.point.reference import Reading
from codegen.model.cell import DEMO_CELL, load_cell
from codegen.poses import xyzabc_from_matrix
from codegen.verify.engine import Options, verify_cell
from codegen.world.cell import part_shape
from codegen.world.solids import Box

ROOT = Path(__file__).resolve().parents[2]
DEMO = ROOT / "generated" / "agv_machine_tending" / "ur" / "agv_machine_tending.script"
TESTMAT = ROOT / "codegen" / "examples" / "pallets" / "testmat_pallet.toml"
PALLET_UR = ROOT / "generated" / "testmat_pallet" / "ur" / "pal_testmat.script"
FAST = Options(cases=1, jobs=1, sweeps=False, scenarios=frozenset({"random"}))


def demo_with_station_solid(tmp_path: Path, line: str) -> Path:
    """The demo cell with `line` added to station 1's (lathe_1's) [station.solids]."""
    text = Path(DEMO_CELL).read_text(encoding="utf-8")
    machine = next(li for li in text.splitlines(keepends=True) if li.startswith("[station.solids]"))
    path = tmp_path / "agv_machine_tending.toml"
    path.write_text(text.replace(machine, machine + line, 1), encoding="utf-8")
    for name in Path(DEMO_CELL).parent.glob("agv_*.csv"):
        (tmp_path / name.name).write_text(name.read_text(encoding="utf-8"), encoding="utf-8")
    return path


def _pose(matrix) -> str:
    return "[" + ", ".join(f"{float(v):.4f}" for v in xyzabc_from_matrix(matrix)) + "]"


def test_a_station_solid_in_the_way_between_its_poses_fails_verify(tmp_path):
    """A 30 mm block of lathe_1's own where the tool passes halfway from chuck_out up to chuck_clear (both moved by
    the reading, as the block is): the generated program fails for that station's case, naming the block; the
    other stations' cases (the block is not at their machines) pass."""
    demo = load_cell(DEMO_CELL)
    station = demo.stations_section().station_by_id(1)
    poses = {p.name: p.matrix() for p in station.path}
    middle = np.eye(4)
    middle[:3, 3] = 0.5 * (poses["chuck_out"][:3, 3] + poses["chuck_clear"][:3, 3])
    block = f"block = {{ box = [30.0, 30.0, 30.0], pose = {_pose(middle)} }}\n"
    cell = load_cell(demo_with_station_solid(tmp_path, block))
    report = verify_cell(cell, [DEMO], ("ur",), FAST)
    (row,) = report.rows
    assert row.first_mismatches and all("station 1 " in m or "lathe_1" in m for m in row.first_mismatches)
    assert all("cuts" in m and "into lathe_1: block (clearance 20 mm)" in m for m in row.first_mismatches)
    assert row.mismatches == 1  # lathe_1's one random case; the other six stations' pass


def test_a_stations_machine_moves_with_the_cases_reading():
    """Seen from the station's own machine, the reference's chuck pose is where it is at the nominal reading, for a
    reading shifted and turned within the limits."""
    cell = load_cell(DEMO_CELL)
    station = cell.stations_section().station_by_id(1)
    scene = cell.kinds["station"].scene
    x, y, theta = station.spec.mark
    chuck = [p.name for p in station.path].index("chuck")

    def seen(reading) -> np.ndarray:
        stage = scene.staged(cell, "ur", Case("random", reading))(0, 0)
        expected = mode_of(station).accepted(cell, reading)[0][0]
        return np.linalg.inv(stage.solids["lathe_1: bed"].pose) @ expected.moves[expected.path_start + chuck].tcp2base

    nominal = seen(Reading(1, x, y, theta))
    moved = seen(Reading(1, x + 6.0, y - 4.0, theta + 3.0))
    assert np.allclose(nominal, moved, atol=1e-6)
    declared = station.solids["bed"].solid2base
    assert not np.allclose(scene.staged(cell, "ur", Case("random", Reading(1, x + 6.0, y - 4.0, theta + 3.0)))(
        0, 0).solids["lathe_1: bed"].pose, declared, atol=1.0)  # it did move


def test_a_stations_part_is_its_own():
    cell = load_cell(DEMO_CELL)
    station = cell.stations_section().station_by_id(1)
    stage = cell.kinds["station"].scene.staged(cell, "ur", Case("random", Reading(1, *station.spec.mark)))(0, 0)
    part = part_shape(cell, stage.part)
    assert isinstance(part, Box) and part.size == (60.0, 60.0, 80.0)


TRANSIT = "    movej(get_inverse_kin(transit, qnear=pal_qnear(row)), a=1.2, v=0.25, r=0.0020)\n"
LOW = "    movej(get_inverse_kin(pal_pose(x + PAL_AX[row], y + PAL_AY[row], z + 5.0000, a), qnear=pal_qnear(row)), " \
      "a=1.2, v=0.25)\n"


def test_a_box_carried_low_through_the_stack_as_built_fails_verify(tmp_path):
    """The pallet program edited so that the box goes from above Q straight to its approach (a joint move, not over
    the transit height): restarted mid-pallet, the carried box (or the arm) cuts through the stack as built there,
    named by its layer or box."""
    text = PALLET_UR.read_text(encoding="utf-8")
    assert text.count(TRANSIT) == 1
    edited = tmp_path / PALLET_UR.name
    edited.write_text(text.replace(TRANSIT, LOW), encoding="utf-8")
    options = Options(cases=1, jobs=1, sweeps=False, scenarios=frozenset({"restart"}))
    report = verify_cell(load_cell(TESTMAT), [edited], ("ur",), options)
    (row,) = report.rows
    stack = re.compile(r"clearance: .* (into|of) pallet testmat: (layer|stack)")
    stacked = [m for m in row.first_mismatches if stack.search(m)]
    assert stacked, row.first_mismatches
    assert all("pal_testmat.script:" in m for m in stacked)
