"""A plant's verify says where a cell's runs came nearer a joint limit than the cell asks, as a cell's verify does."""

from __future__ import annotations

import time
from pathlib import Path

from codegen.model.cell import load_cell
from codegen.model.robot import Margins
from codegen.plant.results import CellResult, PlantReport
from codegen.plant.verify import Pending, _row
from codegen.robot.arms import find_arm
from codegen.robot.expect import ArmStats
from codegen.verify.report import Report, Row

CARTON = Path(__file__).resolve().parents[1] / "kinds" / "cells" / "carton_kuka.toml"


class _Move:
    def __init__(self, joints, line):
        self.joints, self.line = joints, line


def _short_arm() -> ArmStats:
    """A run with A1 at 160 deg (its limit 170: 10 deg) on an arm whose cell asks 15 deg."""

    class Cell:
        class robot:  # the shape ArmStats reads
            arms = {"kuka": find_arm("KR 6 R900 sixx")}
            margins = Margins(15.0, 5.0)

    stats = ArmStats()
    joints = [[0.0, -90.0, 90.0, 0.0, 90.0, 45.0], [160.0, -90.0, 90.0, 0.0, 40.0, 0.0]]
    stats.add(Cell, "kuka", [_Move(j, 20 + i) for i, j in enumerate(joints)], lambda: "held_at_start layer 1 box 2")
    return stats


def _result(arm: ArmStats) -> CellResult:
    cell = load_cell(CARTON)
    report = Report(cell.name, [Row("pallet", "kuka", "pal_half", ["<fresh>/pal_half.src"], cases=1, arm=arm)], 0, 1)
    return _row(Pending("carton.toml", CARTON, cell, ["kuka"], "key", [], time.perf_counter()), report), report


def test_the_plant_prints_the_margin_warning_of_a_cell_as_its_verify_does():
    result, report = _result(_short_arm())
    (said,) = report.margin_warnings()  # what `codegen verify CELL` prints after "warning: "
    assert said.startswith("arm kuka pal_half: 10.0 deg to a joint limit (axis 1 at 160.0 deg, move 2 (line 21)")
    assert result.warnings == [said]
    lines = PlantReport("verify", "plant", [result], 1.0).lines()
    assert f"warning: carton.toml: {said}" in lines, lines
    again = CellResult.from_json(result.as_json())  # a cached result keeps it
    assert again.warnings == [said]


def test_no_warning_where_every_run_keeps_the_margin():
    result, _ = _result(ArmStats())
    assert result.warnings == []
    assert not any(line.startswith("warning:") for line in PlantReport("verify", "plant", [result], 1.0).lines())
