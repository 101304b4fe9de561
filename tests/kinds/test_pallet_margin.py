"""A KUKA pallet cell's joint margins and flips as generate and verify report them: the joint that flips, named."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from codegen.cli import main
from codegen.model.robot import Margins
from codegen.robot.arms import find_arm
from codegen.robot.expect import ArmStats

CARTON = (Path(__file__).resolve().parent / "cells" / "carton_kuka.toml").read_text(encoding="utf-8")
PICK = "pick = [1300.0, 0.0, 150.0, 0.0, 0.0, 180.0]"


def test_a_flip_on_a_linear_move_names_the_axis_its_values_and_the_key(tmp_path):
    """Q low and near the base: the way up from Q (a linear move) straightens the wrist, axis 5 passes 0 deg. The
    refusal names the axis, where it starts and ends, and the key that moves Q, not only "a wrist or elbow flip"."""
    assert PICK in CARTON
    path = tmp_path / "carton.toml"
    path.write_text(CARTON.replace(PICK, "pick = [900.0, 0.0, -550.0, 0.0, 0.0, 180.0]"), encoding="utf-8")
    result = CliRunner().invoke(main, ["generate", str(path), "--out", str(tmp_path / "out")])
    assert result.exit_code == 2, result.output
    assert "layer 2 box 1 up from Q" in result.output
    found = re.search(
        r"axis 5 crosses the wrist singularity \(axes 4 and 6 in line\): from (\S+) to (\S+) deg", result.output
    )
    assert found, result.output
    before, after = float(found[1]), float(found[2])
    assert before * after < 0  # on either side of 0 deg, where the KUKA's wrist is straight
    assert "[[pallet]] pick" in result.output
    assert "Traceback" not in result.output


class _Move:
    def __init__(self, joints, line):
        self.joints, self.line = joints, line


def _stats(asked_deg: float) -> ArmStats:
    class Cell:
        class robot:  # the shape ArmStats reads
            arms = {"kuka": find_arm("KR 6 R900 sixx")}
            margins = Margins(asked_deg, 5.0)

    # A1 at 160 deg, its limit 170 (KUKA's data sheet, the catalogue's source): 10 deg from it
    joints = [[0.0, -90.0, 90.0, 0.0, 90.0, 45.0], [160.0, -90.0, 90.0, 0.0, 40.0, 0.0]]
    stats = ArmStats()
    stats.add(Cell, "kuka", [_Move(j, 20 + i) for i, j in enumerate(joints)], lambda: "restart layer 1 box 2")
    return stats


def test_a_run_nearer_a_joint_limit_than_the_cell_asks_is_named_with_the_margin_asked():
    short = _stats(15.0).shortfall()
    assert short is not None
    assert short.startswith("10.0 deg to a joint limit (axis 1 at 160.0 deg, move 2 (line 21), restart layer 1 box 2)")
    assert "less than the 15 deg the cell asks (cell.robot.joint_margin_deg)" in short
    assert _stats(10.0).shortfall() is None  # exactly the margin asked: kept


def test_verify_warns_where_any_run_is_nearer_a_joint_limit_than_the_cell_asks(tmp_path):
    """The carton cell asks 5 deg (the default joint margin). verify's report names its least margin over every run
    (the restarts' too, not only the full cycle generate proves); below 5 deg a warning names it, the move, the
    case and the margin asked, on every kind's report alike."""
    path = tmp_path / "carton.toml"
    path.write_text(CARTON, encoding="utf-8")
    result = CliRunner().invoke(main, ["verify", str(path), "--target", "kuka"])
    assert result.exit_code == 0, result.output
    least = re.search(
        r"least margin to a joint limit (\S+) deg \((axis \d at \S+ deg, move .*?)\), of axis 5", result.output
    )
    assert least, result.output
    warned = [line for line in result.stderr.splitlines() if "the cell asks" in line]
    if float(least[1]) < 5.0:
        assert warned == [
            f"warning: arm kuka pal_half: {least[1]} deg to a joint limit ({least[2]}), less than the 5 deg the cell "
            "asks (cell.robot.joint_margin_deg)"
        ], result.stderr
    else:
        assert warned == []


def _generate_margin(cell, target: str) -> float:
    """The least joint margin generate states for the cell's pallets on the target (codegen/kinds/pallet/reach.py)."""
    from codegen.kinds.pallet.plan import configurations
    from codegen.kinds.pallet.reach import check_pallet
    from codegen.kinds.pallet.section import pallets_of

    return min(
        check_pallet(cell, p, target, configurations(cell, p, target)).joint_margin_deg for p in pallets_of(cell)
    )


def _held_at_start(cell, source):
    from support.programs import verify_one

    return verify_one(cell, source, cases=1, scenarios=["held_at_start"], clearance=False)


def test_a_restart_with_a_box_held_keeps_the_margin_generate_states(tmp_path):
    """The carton cell names a Status but no Turn at each box's transit: from home a PTP there takes the turn nearest
    home, axis 6 one turn off the cycle's (1.0 deg from its limit where generate says 22.2). The restart goes above
    the pallet's centre in axis values first, in the cycle's turns: verify's held_at_start runs keep generate's
    margin (within the joints' tolerance)."""
    from support.programs import sources

    from codegen.model.cell import load_cell
    from codegen.robot.expect import JOINT_TOLERANCE_DEG

    path = tmp_path / "carton.toml"
    path.write_text(CARTON, encoding="utf-8")
    cell = load_cell(path)
    (program,) = sources(cell, "kuka", "pallet")
    row = _held_at_start(cell, program)
    assert row.cases >= 2 and row.mismatches == 0, row.first_mismatches
    said = _generate_margin(cell, "kuka")
    assert said > 20.0, said  # the cell's figure (generate: 22.2 deg)
    assert abs(row.arm.joint_margin_deg - said) <= JOINT_TOLERANCE_DEG, (row.arm.summary(), said)
    assert row.arm.shortfall() is None


def _wrist_stats(a5_deg: float, asked_deg: float = 5.0) -> ArmStats:
    class Cell:
        class robot:  # the shape ArmStats reads
            arms = {"kuka": find_arm("KR 6 R900 sixx")}
            margins = Margins(5.0, asked_deg)

    # axis 5 at 0 deg lines up axes 4 and 6 (KUKA): the second move's wrist a5_deg from its singularity
    joints = [[0.0, -90.0, 90.0, 0.0, 90.0, 45.0], [10.0, -90.0, 90.0, 0.0, a5_deg, 0.0]]
    stats = ArmStats()
    stats.add(Cell, "kuka", [_Move(j, 30 + i) for i, j in enumerate(joints)], lambda: "start_away layer 1 box 1")
    return stats


def test_a_run_nearer_the_wrist_singularity_than_the_cell_asks_is_named_like_the_joint_margin():
    from codegen.verify.report import Report, Row

    stats = _wrist_stats(2.0)
    short = stats.wrist_shortfall()
    assert short == (
        "2.0 deg from the wrist singularity (axis 5 at 2.0 deg, move 2 (line 31), start_away layer 1 box 1), less "
        "than the 5 deg the cell asks (cell.robot.wrist_margin_deg)"
    )
    assert stats.shortfall() is None  # the joints keep their margin: only the wrist is said
    summary = stats.summary()
    assert summary["wrist_margin_at"].startswith("axis 5 at 2.0 deg, move 2 (line 31)")
    assert summary["wrist_margin_asked_deg"] == 5.0 and summary["wrist_margin_deg"] == 2.0  # the keys before, kept
    report = Report("carton", [Row("pallet", "kuka", "pal_half", [], cases=1, arm=stats)], 0, 1)
    assert report.margin_warnings() == [f"arm kuka pal_half: {short}"]


def test_no_wrist_warning_where_every_run_keeps_the_wrist_margin():
    from codegen.verify.report import Report, Row

    stats = _wrist_stats(40.0)
    assert stats.wrist_shortfall() is None
    assert _wrist_stats(5.0).wrist_shortfall() is None  # exactly the margin asked: kept
    assert Report("carton", [Row("pallet", "kuka", "p", [], cases=1, arm=stats)], 0, 1).margin_warnings() == []


def test_the_safe_pose_takes_the_turns_the_cycle_has(tmp_path):
    """The carton cell's plan names above Q with axis 6 at -180 (of the two sides a half turn allows): the cycle then
    works with axis 6 near -270 at the boxes. The safe pose (the way home's, and a held restart's way onto the
    pallet) in axis values is the solution nearest the cycle's first entry in those turns (-270), not +90: from
    any box no axis turns more than half a turn to reach it."""
    from codegen.kinds.pallet.plan import configurations
    from codegen.kinds.pallet.reach import SAFE_KEY, full_cycle, joints_of
    from codegen.kinds.pallet.section import pallets_of
    from codegen.model.cell import load_cell

    path = tmp_path / "carton.toml"
    path.write_text(CARTON, encoding="utf-8")
    cell = load_cell(path)
    (pallet,) = pallets_of(cell)
    named = configurations(cell, pallet, "kuka")
    assert not named.whole and SAFE_KEY in named.anchors  # no Turn named: the safe pose in axis values
    moves = full_cycle(cell, pallet)
    cycle = joints_of(cell, "kuka", moves, "carton", pallet, named)
    entries = [q for m, q in zip(moves, cycle, strict=True) if isinstance(named.key(pallet, m), tuple)]
    safe = named.anchors[SAFE_KEY]
    turn = np.abs(safe - entries[0])
    assert np.max(turn) <= 180.0, (safe, entries[0])
    assert safe[5] == pytest.approx(-270.0, abs=1.0)


EXAMPLES = Path(__file__).resolve().parents[2] / "codegen" / "examples"
PALLET_CELLS = [
    *sorted((EXAMPLES / "pallets").glob("*.toml")),
    *sorted((EXAMPLES / "plant" / "pallets").glob("*.toml")),
    Path(__file__).resolve().parent / "cells" / "carton_kuka.toml",
]


@pytest.mark.slow  # a held_at_start verify of every pallet program of every cell with an arm
@pytest.mark.parametrize("path", PALLET_CELLS, ids=lambda p: p.stem)
def test_every_pallet_cells_held_restart_keeps_the_margin_generate_states(path):
    """generate states the least joint margin over the full cycle and at home; a restart with an item held runs a
    part of the cycle from home, so verify's held_at_start runs come no nearer a limit than that."""
    from support.programs import sources

    from codegen.model.cell import load_cell
    from codegen.robot.expect import JOINT_TOLERANCE_DEG, margins

    cell = load_cell(path)
    checked = 0
    for target in cell.targets:
        if cell.robot is None or target not in cell.robot.arms:
            continue
        home = margins(cell.robot.arms[target], np.asarray(cell.robot.home[target], dtype=float))[0]
        said = min(_generate_margin(cell, target), home)
        for program in sources(cell, target, "pallet"):
            row = _held_at_start(cell, program)
            assert row.cases >= 2 and row.mismatches == 0, row.first_mismatches
            assert row.arm.joint_margin_deg >= said - JOINT_TOLERANCE_DEG, (target, row.arm.summary(), said)
            checked += 1
    assert checked or path.stem.startswith("tray"), path  # the dtrans tray cell has no arm
