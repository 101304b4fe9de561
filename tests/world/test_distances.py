"""The distance engine against hand-computed geometry, the link frames and the catalogue's link shapes."""

from __future__ import annotations

import math

import numpy as np
import pytest

from codegen.robot.arms import ArmError, arm_from_table, catalogue
from codegen.world.bodies import arm_bodies, self_pairs
from codegen.world.engine import Scene, distance
from codegen.world.solids import Box, Capsule, Cylinder, Floor, World, tool_cylinder, translation


def turned_z(angle_deg: float, x: float, y: float, z: float) -> np.ndarray:
    c, s = math.cos(math.radians(angle_deg)), math.sin(math.radians(angle_deg))
    out = translation(x, y, z)
    out[:2, :2] = [[c, -s], [s, c]]
    return out


def test_capsule_over_a_box_at_a_known_gap():
    capsule = Capsule(20.0, (0.0, 0.0, 0.0), (100.0, 0.0, 0.0))
    cube = Box((50.0, 50.0, 50.0), translation(50.0, 0.0, 100.0))
    d, near_capsule, near_box = distance(capsule, np.eye(4), cube, np.eye(4))
    assert d == pytest.approx(100.0 - 25.0 - 20.0, abs=1e-6)  # box bottom at z = 75, capsule top at z = 20
    assert near_capsule[2] == pytest.approx(20.0, abs=1e-6)
    assert near_box[2] == pytest.approx(75.0, abs=1e-6)


def test_capsule_end_near_a_turned_box_corner():
    capsule = Capsule(20.0, (0.0, 0.0, 0.0), (100.0, 0.0, 0.0))
    cube = Box((100.0, 100.0, 100.0), turned_z(45.0, 200.0, 0.0, 0.0))  # a vertical edge points at the capsule
    d, _, _ = distance(capsule, np.eye(4), cube, np.eye(4))
    assert d == pytest.approx(200.0 - 50.0 * math.sqrt(2.0) - 100.0 - 20.0, abs=1e-6)


def test_overlap_is_negative_depth_and_poses_compose():
    capsule = Capsule(50.0, (0.0, 0.0, -200.0), (0.0, 0.0, 200.0))
    floor = Floor(100.0)
    d, _, _ = distance(capsule, translation(0.0, 0.0, 300.0), floor, np.eye(4))  # lowest point at 50
    assert d == pytest.approx(-50.0, abs=1e-6)
    cylinder = Cylinder(30.0, 100.0, turned_z(0.0, 0.0, 0.0, 0.0))
    d, _, _ = distance(cylinder, translation(500.0, 0.0, 0.0), Box((10.0, 10.0, 10.0)), translation(400.0, 0.0, 0.0))
    assert d == pytest.approx(500.0 - 30.0 - 400.0 - 5.0, abs=1e-6)


def test_ur_link_frames_match_the_dh_elbow_written_out():
    arm = catalogue()["UR5e"]
    kin = arm.kin
    rng = np.random.default_rng(4)
    for q in rng.uniform(-180.0, 180.0, (20, 6)):
        q1, q2 = math.radians(q[0]), math.radians(q[1])
        reach = kin.a2 * math.cos(q2)  # DH: Rz(q1) Tz(d1) Rx(90) Rz(q2) Tx(a2) puts the elbow here
        elbow = (math.cos(q1) * reach, math.sin(q1) * reach, kin.d1 + kin.a2 * math.sin(q2))
        assert kin.link_frames(q)[2, :3, 3] == pytest.approx(elbow, abs=1e-9)
        assert np.allclose(kin.link_frames(q)[6], kin.fk(q), atol=1e-9)


def test_opw_link_frames_end_at_the_flange_and_wrist_centre():
    rng = np.random.default_rng(5)
    for name in ("KR 6 R900 sixx", "IRB 4600-60/2.05"):
        kin = catalogue()[name].kin
        q = rng.uniform(-150.0, 150.0, (30, 6))
        frames = kin.link_frames(q)
        assert np.allclose(frames[:, 6], kin.fk(q), atol=1e-9)
        assert np.allclose(frames[:, 4, :3, 3], kin.wrist_center(q), atol=1e-9)
        theta = np.radians(kin.signs[0] * q[:, 0] + kin.offsets_deg[0])  # axis 2 at (a1, 0, c1) turned by theta1
        axis2 = np.c_[kin.a1 * np.cos(theta), kin.a1 * np.sin(theta), np.full(len(q), kin.c1)]
        assert np.allclose(frames[:, 2, :3, 3], axis2, atol=1e-9)


def test_every_catalogue_arm_has_links_and_stands_clear_of_itself_at_home():
    tool = translation(0.0, 0.0, 150.0)
    for arm in catalogue().values():
        assert arm.links and arm.links_source.startswith("estimates")
        scene = Scene(arm, World({}), tool=tool_cylinder(tool, 25.0))
        found = scene.nearest(np.array(arm.home_deg)[None])[0]
        assert found is not None and found.distance > 0, (arm.model, found)


def test_self_pairs_skip_neighbours_and_the_allowed_pairs():
    tool = tool_cylinder(translation(0.0, 0.0, 150.0), 25.0)
    ur = catalogue()["UR5e"]
    bodies = arm_bodies(ur, tool)
    names = {(bodies[i].name, bodies[j].name) for i, j in self_pairs(ur, bodies)}
    assert ("base", "forearm") in names and ("shoulder", "wrist_2") in names and ("forearm", "tool") in names
    assert ("upper_arm", "forearm") not in names and ("forearm", "wrist_3") not in names  # frames 3 and 5
    abb = catalogue()["IRB 140"]
    bodies = arm_bodies(abb, tool)
    names = {(bodies[i].name, bodies[j].name) for i, j in self_pairs(abb, bodies)}
    assert ("forearm", "flange") not in names  # self_allowed [3, 6]: they meet in the wrist's fork
    assert ("forearm", "tool") in names  # the allowance is the arm's own, not the tool's


def test_a_folded_elbow_reaches_the_base():
    arm = catalogue()["UR5e"]
    scene = Scene(arm, World({}))
    stretched, folded = [0.0, 0.0, 0.0, -90.0, -90.0, 0.0], [0.0, 0.0, 165.0, -90.0, -90.0, 0.0]
    clear, hit = scene.nearest(np.array([stretched, folded]))
    assert clear is None or clear.distance > 0
    assert hit is not None and hit.distance < 0 and hit.body in ("base", "shoulder") and hit.other.startswith("wrist")


def test_link_shape_errors_name_the_key():
    table = {"model": "X", "family": "ur", "limits_deg": [[-360, 360]] * 6, "home_deg": [0, -90, 90, -90, -90, 0],
             "params": {"d1": 150, "a2": -240, "a3": -210, "d4": 130, "d5": 85, "d6": 92}}
    link = {"name": "a", "frame": 1, "a": [0, 0, 0], "b": [0, 0, 1], "radius": 5}
    with pytest.raises(ArmError, match=r"arm\.links\[0\]\.frame"):
        arm_from_table({**table, "links": [{**link, "frame": 9}]}, "arm")
    with pytest.raises(ArmError, match=r"arm\.links\[0\]\.radius"):
        arm_from_table({**table, "links": [{**link, "radius": 0}]}, "arm")
    with pytest.raises(ArmError, match=r"arm\.links\[0\]\.size: unknown key"):
        arm_from_table({**table, "links": [{**link, "size": 1}]}, "arm")
    with pytest.raises(ArmError, match=r"arm\.self_allowed\[0\]"):
        arm_from_table({**table, "self_allowed": [[1]]}, "arm")
