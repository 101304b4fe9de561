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


def _testmat_cycle(target: str):
    cell = load_cell(EXAMPLES["testmat_pallet"])
    return cell, cell.kinds["pallet"].scene.paths(cell, [target])


def test_a_fence_through_the_pallets_way_home_is_refused(tmp_path):
    """The KUKA's way home after a stop at the first box's place, the box held: its last move, a joint move from
    above the pallet to home; a fence's rail (a 10 mm cube) where the held box's centre is halfway along it (forward
    kinematics of the mean joints; the box hangs 13 mm under the TCP). The full cycle never carries a box there."""
    cell, paths = _testmat_cycle("kuka")
    arm, tcp2flange = cell.robot.arms["kuka"], cell.robot.tool.tcp2flange
    way = next(p for p in paths if "the way home from layer 1 box 1" in p.moves[0].where)
    before, last = way.moves[-2], way.moves[-1]
    assert last.carrying
    middle = arm.kin.fk(0.5 * (np.asarray(before.joints) + np.asarray(last.joints))) @ tcp2flange
    rail = np.eye(4)
    rail[:3, 3] = (middle @ np.array([0.0, 0.0, 13.0, 1.0]))[:3]
    extra = f"[cell.world]\nsolids.fence_rail = {{ box = [10.0, 10.0, 10.0], pose = {_pose(rail)} }}\n"
    cell = with_world(tmp_path, "testmat_pallet", "", "[cell.io]", extra)
    with pytest.raises(GenerateError) as caught:
        check_clearance(cell, ["kuka"])
    said = str(caught.value)
    assert said.startswith("pallet 'testmat' the way home from layer 1 box 1 target: home (kuka, KR 6 R900 sixx): the ")
    assert "the part touches the solid 'fence_rail'" in said


def test_a_carried_box_that_sweeps_a_neighbouring_stack_is_refused(tmp_path):
    """The KUKA's first transit with a box (the joint move from Q over to the pallet): a stack of boxes declared
    where the carried box's centre is halfway along it (a 20 mm cube there, 5 mm lower: inside the 26 mm box but for
    2 mm at its bottom, 8 mm under the tool's tip). The part is refused against it, not the tool."""
    cell, paths = _testmat_cycle("kuka")
    arm, tcp2flange = cell.robot.arms["kuka"], cell.robot.tool.tcp2flange
    moves = paths[0].moves
    k = next(i for i, m in enumerate(moves) if m.kind == "joint" and m.carrying)
    middle = arm.kin.fk(0.5 * (np.asarray(moves[k - 1].joints) + np.asarray(moves[k].joints))) @ tcp2flange
    centre = middle @ np.array([0.0, 0.0, 13.0 + 5.0, 1.0])  # the box hangs along the tool's z from the TCP
    stack = np.eye(4)
    stack[:3, 3] = centre[:3]
    extra = f"[cell.world]\nsolids.stack_b = {{ box = [20.0, 20.0, 20.0], pose = {_pose(stack)} }}\n"
    cell = with_world(tmp_path, "testmat_pallet", "", "[cell.io]", extra)
    with pytest.raises(GenerateError) as caught:
        check_clearance(cell, ["kuka"])
    said = str(caught.value)
    assert said.startswith(f"{moves[k].where} (kuka, KR 6 R900 sixx): the part touches the solid 'stack_b'")
