"""The pallet, conveyor and laser reach proofs name the pose nearest the wrist singularity (as the stations' do), in
their text, their --json and their refusal, not only the pose nearest a joint limit."""

from __future__ import annotations

import numpy as np
import pytest

from codegen.generate import GenerateError, check_envelope
from codegen.model.cell import load_cell
from codegen.robot import solve
from codegen.robot.margins import singular_distance, wrist_angle
from tests.kinds.test_pallet import EXAMPLES, TESTMAT

ROOT = EXAMPLES.parent


def _wrist_nearest(cell, target: str, named_poses) -> tuple[str, float]:
    """The pose nearest the wrist singularity along a path taken from home by the nearest solution, and its
    distance: worked out here from the arm's kinematics, pose by pose."""
    robot, arm = cell.robot, cell.robot.arms[target]
    flange = solve.flange_poses(np.array([p for _n, p in named_poses]), robot.tool.tcp2flange)
    q, out = np.asarray(robot.home[target], dtype=float), []
    for (name, _p), sols in zip(named_poses, solve.branches(arm, flange), strict=True):
        q, _chosen = solve.nearest(arm, sols, q)
        out.append((float(np.min(singular_distance(wrist_angle(arm, q)))), name))
    distance, name = min(out, key=lambda d: d[0])
    return name, distance


def test_the_laser_proof_names_the_pose_nearest_the_wrist_singularity():
    from codegen.kinds.laser.reach import path

    cell = load_cell(ROOT / "laser" / "laser_tcp.toml")
    reports = {r.target: r for r in check_envelope(cell, None) if "laser" in r.subject()[0]}
    assert set(reports) == {"ur", "kuka", "abb"}
    for target, report in reports.items():
        name, distance = _wrist_nearest(cell, target, path(cell))
        assert report.as_json()["wrist_pose"] == name
        assert report.wrist_margin_deg == pytest.approx(distance, abs=1e-9)
        assert f"wrist {distance:.1f} deg from its singularity (pose {name})" in report.text()
    # on the ABB the two are different poses: the joint-margin pose alone did not say where the wrist is
    assert reports["abb"].worst == "circle 1" and reports["abb"].wrist_pose == "circle 2"


def test_the_conveyor_proof_names_the_pose_nearest_the_wrist_singularity():
    from codegen.kinds.conveyor.reach import follow_mm, lines

    cell = load_cell(ROOT / "conveyor" / "belt_pick.toml")
    reports = [r for r in check_envelope(cell, None) if r.subject()[0] == "conveyor window"]
    assert reports
    for report in reports:
        found = []  # each line from home, as the proof takes them
        for what, poses in lines(cell, follow_mm(cell, report.target)):
            found.append(_wrist_nearest(cell, report.target, [(what, p) for p in poses])[::-1])
        distance, name = min(found)
        assert report.as_json()["wrist_pose"] == name and report.wrist_margin_deg == pytest.approx(distance)
        assert f"(pose {name})" in report.text()


def test_a_pallet_refused_for_its_wrist_names_the_pose_nearest_the_singularity(tmp_path):
    """The refusal named the pose nearest a joint limit only."""
    old = "origin = [650.0, -50.0, 50.0], x_point = [750.0, -50.0, 50.0], xy_point = [650.0, 30.0, 50.0]"
    new = "origin = [500.0, -100.0, -200.0], x_point = [600.0, -100.0, -200.0], xy_point = [500.0, -20.0, -200.0]"
    path = tmp_path / "pallet.toml"
    floor = "[cell.world]\nfloor_z_mm = -400.0\n\n[cell.io]"  # under the lowered pallet (its top at -200 mm)
    assert "[cell.world]" not in TESTMAT and "[cell.io]" in TESTMAT
    path.write_text(TESTMAT.replace(old, new, 1).replace("[cell.io]", floor, 1))
    with pytest.raises(GenerateError) as refused:
        check_envelope(load_cell(path), ["kuka"])
    message = str(refused.value)
    assert "the wrist 0." in message
    assert "(the wrist nearest its singularity: layer " in message, message


def test_the_pallet_proof_names_the_pose_nearest_the_wrist_singularity():
    reports = [r for r in check_envelope(load_cell(EXAMPLES / "testmat_pallet.toml"), ["kuka"]) if r.target == "kuka"]
    pallet = next(r for r in reports if r.subject()[0].startswith("pallet"))
    assert pallet.as_json()["wrist_pose"] == pallet.wrist_pose != ""
    assert f"(pose {pallet.wrist_pose})" in pallet.text()
