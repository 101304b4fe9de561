"""The arm's joints chosen once per run and check: the remembered choice is the one made afresh, bit for bit."""

from __future__ import annotations

import glob
import struct

import numpy as np
import pytest

from codegen.kinds.station.joints import expected_joints
from codegen.kinds.station.plan import taught_poses
from codegen.kinds.station.section import stations_of
from codegen.model.cell import load_cell
from codegen.robot import solve
from codegen.verify import checks, runner
from codegen.verify.programs import fresh_sources

CELLS = sorted(
    f for f in glob.glob("codegen/examples/*.toml") + glob.glob("codegen/examples/*/*.toml") if "/plant/" not in f
)
CASES = 3


def _exact(value):
    """A value as bytes where it holds floats, so that equal means equal bit for bit (NaN included)."""
    if isinstance(value, np.ndarray):
        return (value.dtype.str, value.shape, value.tobytes())
    if isinstance(value, float):
        return struct.pack("<d", value)
    if isinstance(value, list | tuple):
        return tuple(_exact(v) for v in value)
    return value


def _checked(monkeypatch, cell_file: str) -> list:
    """Every common check's output (problem, position and orientation errors) and the planned joints it judged
    against, for CASES cases of every program of the cell on every target."""
    out = []
    real = checks.Checker.check

    def check(self, expected, trace, *args):
        got = real(self, expected, trace, *args)
        planned = expected.planned_joints() if expected.planned_joints is not None else None
        out.append((_exact(got), _exact(planned)))
        return got

    monkeypatch.setattr(checks.Checker, "check", check)
    cell = load_cell(cell_file)
    for source in fresh_sources(cell, list(cell.targets)):
        model = source.model or cell
        cases = cell.kinds[source.kind].verify.cases(model, source, CASES, 0)
        runner.run_cases(cell, source, cases[:: max(1, len(cases) // CASES)][:CASES], 200_000)
    return out


def _counted(monkeypatch, remembered: bool) -> list[int]:
    calls = [0]
    fresh = solve._nearest_fresh

    def counting(arm, solutions, q_ref):
        calls[0] += 1
        return fresh(arm, solutions, q_ref)

    monkeypatch.setattr(solve, "_nearest_fresh", counting)
    if not remembered:
        monkeypatch.setattr(solve, "_nearest_one", counting)
    solve._NEAREST.clear()
    return calls


SLOW = {"codegen/examples/pallets/eur_pallet.toml"}  # its 3 cases run for about 20 s: with the slow tests


@pytest.mark.parametrize("cell_file", [pytest.param(f, marks=pytest.mark.slow) if f in SLOW else f for f in CELLS])
def test_check_same_with_and_without_the_remembered_joints(monkeypatch, cell_file):
    with monkeypatch.context() as m:
        _checked(m, cell_file)  # the cell's plans and programs made once, so both runs below ask the same
    with monkeypatch.context() as m:
        afresh_calls = _counted(m, remembered=False)
        afresh = _checked(m, cell_file)
    with monkeypatch.context() as m:
        reused_calls = _counted(m, remembered=True)
        reused = _checked(m, cell_file)
    assert afresh, "no check ran"
    assert reused == afresh
    if afresh_calls[0]:  # a cell with an arm: the check's and the run's questions are asked once
        assert reused_calls[0] < afresh_calls[0]


def test_a_move_without_solutions_is_solved():
    """expected_joints solves the reference's pose of a move the run left without solutions (a joint target)."""
    cell = load_cell("codegen/examples/agv_machine_tending.toml")
    target, station = "kuka", stations_of(cell)[0]
    poses, _ = taught_poses(cell, target, station)
    moves = []
    for pose in poses:
        moves.append(type("Move", (), {"pose_name": pose.name, "tcp2base": pose.tcp2base})())
    start = np.asarray(cell.robot.home[target], dtype=float)
    arm = cell.robot.arms[target]
    flanges = solve.flange_poses(np.array([m.tcp2base for m in moves]), cell.robot.tool.tcp2flange)
    given = [solve.branches(arm, flanges[i : i + 1])[0] for i in range(len(moves))]  # one pose at a time, as missing
    whole = expected_joints(cell, target, station, tuple(moves), start, given)
    for missing in range(len(moves)):
        solved = [None if i == missing else s for i, s in enumerate(given)]
        got = expected_joints(cell, target, station, tuple(moves), start, solved)
        assert not np.isnan(got[missing]).any()
        assert _exact(got) == _exact(whole)
    # none given: all solved in one batch (the batched inverse kinematics rounds apart from one pose's in the last bit)
    assert np.allclose(expected_joints(cell, target, station, tuple(moves), start), whole, rtol=0, atol=1e-9)
