"""generate refuses a cell whose planned moves come within the clearance of a solid, naming the move, the body (link,
tool or part) and the solid; each variant is built here from geometry computed apart from the proof (the arm's
forward kinematics along the move), and the bundled cells' own solids stand where their programs clear them."""

from __future__ import annotations

import re

import numpy as np
import pytest
from support.cells import EXAMPLES

from codegen.generate import GenerateError, check_clearance
from codegen.model.cell import load_cell
from codegen.poses import xyzabc_from_matrix

UR_HOME = np.array([180.0, -90.0, 90.0, -90.0, -90.0, 0.0])


def with_world(tmp_path, name: str, text: str, before: str, extra: str, targets: str | None = None):
    """A bundled cell with `extra` lines put before the first line that starts with `before` (and its targets)."""
    source = EXAMPLES[name].read_text(encoding="utf-8")
    line = next(li for li in source.splitlines() if li.startswith(before))
    source = source.replace(line, extra + "\n" + line, 1)
    if targets is not None:
        source = re.sub(r"^targets = .*$", f"targets = {targets}", source, count=1, flags=re.M)
    path = tmp_path / f"{name}.toml"
    path.write_text(source + text, encoding="utf-8")
    return load_cell(path)


def _pose(matrix) -> str:
    return "[" + ", ".join(f"{float(v):.4f}" for v in xyzabc_from_matrix(matrix)) + "]"


def test_a_machine_moved_into_the_path_between_home_and_a_station_is_refused(tmp_path):
    """The UR's first move of station 1 (a joint move from home to its approach): the tool's tip halfway along it
    (forward kinematics of the mean joints: a joint move interpolates every axis); a 100 mm cube there."""
    demo = load_cell(EXAMPLES["agv_machine_tending"])
    arm, tcp2flange = demo.robot.arms["ur"], demo.robot.tool.tcp2flange
    approach = demo.kinds["station"].scene.paths(demo, ["ur"])[0].moves[0]
    middle = arm.kin.fk(0.5 * (UR_HOME + approach.joints)) @ tcp2flange
    extra = f"solids.lathe_3 = {{ box = [100.0, 100.0, 100.0], pose = {_pose(middle)} }}"
    cell = with_world(tmp_path, "agv_machine_tending", "", "solids.cabinet", extra)
    with pytest.raises(GenerateError) as caught:
        check_clearance(cell, ["ur"])
    said = str(caught.value)
    assert said.startswith("station 1 'lathe_1' pose 'approach' (nominal reading) (ur, UR10e): the ")
    assert "'lathe_3'" in said and "mm into it" in said and "cell.world.clearance_mm" in said
    assert re.search(r"the (tool|wrist_\d|forearm) touches", said)
