"""Joint margins are one rule (codegen.robot.margins): generate's home line, the reach proofs, verify's figures."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
from click.testing import CliRunner

from codegen.cli import main
from codegen.model.cell import EXAMPLES_DIR
from codegen.model.robot import Margins
from codegen.robot.arms import find_arm
from codegen.robot.expect import ArmStats
from codegen.robot.margins import joint_margins, least_joint_margin

BENCH = EXAMPLES_DIR / "thermometer_bench.toml"
CODEGEN = Path(__file__).resolve().parents[2] / "codegen"


def test_generate_prints_the_home_margin(tmp_path):
    # KR 6 R900 sixx: A5 within +-120 deg (KUKA's specification, the catalogue's source); the bench's KUKA home has
    # A5 at 90 deg: 30 deg to the limit. UR5e: every axis +-360 deg; its home's axis 2 at -90: 270 deg.
    out = CliRunner().invoke(main, ["generate", str(BENCH), "--out", str(tmp_path)])
    assert out.exit_code == 0, out.output
    assert "home kuka (KR 6 R900 sixx): 30.0 deg to the nearest joint limit (axis 5 at 90 deg)" in out.output
    assert re.search(r"home ur \(UR5e\): 270\.0 deg to the nearest joint limit \(axis \d at -?90 deg\)", out.output)
    data = json.loads(CliRunner().invoke(main, ["generate", str(BENCH), "--out", str(tmp_path), "--json"]).output)
    kuka = next(h for h in data["home"] if h["target"] == "kuka")
    assert kuka["joint_margin_deg"] == 30.0 and kuka["joint_axis"] == 5 and kuka["home"][4] == 90.0


def test_the_margin_is_the_distance_to_the_nearer_limit():
    arm = find_arm("KR 6 R900 sixx")
    joints = np.array([[0.0, -90.0, 90.0, 0.0, 90.0, 45.0], [160.0, -90.0, 90.0, 0.0, 10.0, 0.0]])
    # by hand from the limits A1 +-170, A2 -190..45, A3 -120..156, A4 +-185, A5 +-120, A6 +-350
    assert np.allclose(joint_margins(arm, joints)[0], [170, 100, 66, 185, 30, 305])
    assert least_joint_margin(arm, joints) == (10.0, (1, 0))  # A1 at 160 deg of 170

    class Move:
        def __init__(self, joints, line):
            self.joints, self.line = joints, line

    class Cell:
        class robot:  # the shape ArmStats reads
            arms = {"kuka": arm}
            margins = Margins(5.0, 5.0)

    stats = ArmStats()
    stats.add(Cell, "kuka", [Move(j, 10 + i) for i, j in enumerate(joints)])
    assert stats.joint_margin_deg == 10.0 and stats.joint_margin_at.startswith("axis 1 at 160.0 deg, move 2 (line 11)")


def test_no_second_formula_for_a_joint_margin():
    """The distance to a joint limit is computed in codegen/robot/margins.py alone (a limit check, inside or not, is
    another question and may live elsewhere)."""
    formulas = re.compile(r"np\.minimum\([^\n]*limits|low \+ margin|high - margin|limits\[:, 1\] - ")
    found = [
        f"{path.relative_to(CODEGEN)}:{i}"
        for path in sorted(CODEGEN.rglob("*.py"))
        if path.name != "margins.py" or path.parent.name != "robot"
        for i, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1)
        if formulas.search(line)
    ]
    assert found == []
