"""Moves checked along their whole path: a box between two clear end poses, a plate thinner than a coarse step,
a linear move solved along its line, and the UR5e posture that puts the elbow under the pick height."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from codegen.robot import solve
from codegen.robot.arms import catalogue
from codegen.world.engine import Scene, distance
from codegen.world.solids import Box, Floor, World, tool_cylinder, translation
from codegen.world.sweep import CLEARANCE_MM, Unresolved, _grid, check_path, joint_path, linear_path, reach

UR5E = catalogue()["UR5e"]
HOME = np.array(UR5E.home_deg)
TOOL = translation(0.0, 0.0, 150.0)


def tip_at(q) -> np.ndarray:
    return (UR5E.kin.fk(np.asarray(q, dtype=float)) @ TOOL)[:3, 3]


def swing(plate: Box, tool_radius: float = 25.0) -> tuple[Scene, np.ndarray, np.ndarray]:
    """Axis 1 from -60 to +60 deg through home, the tool tip passing through plate's place at home (the arm's own
    links not checked: the plate is the only thing to find)."""
    scene = Scene(UR5E, World({"plate": plate}), tool=tool_cylinder(TOOL, tool_radius), self_check=False)
    start, end = HOME.copy(), HOME.copy()
    start[0], end[0] = -60.0, 60.0
    return scene, start, end


def tangential_plate(thickness: float) -> Box:
    """A plate thin along the tip's direction of travel at home (axis 1 turning), 10 mm into the tool's end."""
    tip = tip_at(HOME)
    along = np.cross([0.0, 0.0, 1.0], tip)  # the tip's direction of travel
    along[2] = 0.0
    along /= np.linalg.norm(along)
    pose = np.eye(4)
    pose[:3, 0] = along
    pose[:3, 2] = (0.0, 0.0, 1.0)
    pose[:3, 1] = np.cross(pose[:3, 2], along)
    pose[:3, 3] = tip - (0.0, 0.0, 40.0 - 10.0)  # 80 mm high, its top 10 mm above the tip
    return Box((thickness, 60.0, 80.0), pose)


def test_a_joint_move_through_a_box_its_end_poses_clear():
    scene, start, end = swing(tangential_plate(60.0))
    ends = scene.nearest(np.array([start, end]))
    assert all(found is None or found.distance > 200.0 for found in ends)  # neither end comes near
    result = check_path(scene, joint_path(start, end), start)
    assert result.distance < 0 and result.other == "plate" and result.body == "tool"
    # home lies halfway; the tool (radius 25) meets the 60 mm plate within +-55 mm of the tip's 509.6 mm circle
    assert result.s == pytest.approx(0.5, abs=55.0 / 509.6 / math.radians(120.0))


def test_a_plate_thinner_than_a_coarse_step_is_found():
    scene, start, end = swing(tangential_plate(1.0), tool_radius=10.0)
    coarse = np.linspace(start, end, 16)  # the tip moves about 71 mm between these samples, none at home
    assert all(found is None or found.distance > CLEARANCE_MM for found in scene.nearest(coarse))
    result = check_path(scene, joint_path(start, end), start)
    assert result.distance < CLEARANCE_MM and result.other == "plate"
    assert result.lower_bound < 0  # the guarantee admits contact


def test_the_step_follows_the_distance():
    """Far from the plate the samples lie far apart (the step grows with the distance), near it at most half the
    clearance of travel apart: fewer samples than a fixed half-clearance step, and more where the clearance is
    smaller."""
    scene, start, end = swing(tangential_plate(1.0))
    weights = np.radians(reach(scene))
    fixed = weights @ np.abs(end - start) / (CLEARANCE_MM / 2.0)
    coarse = check_path(scene, joint_path(start, end), start, CLEARANCE_MM)
    fine = check_path(scene, joint_path(start, end), start, 5.0)
    assert coarse.samples < fixed / 2
    assert fine.samples > coarse.samples
    # the tip's own travel per step of the bound stays under it: the bound holds for a point the test follows itself
    steps = np.linspace(start, end, math.ceil(weights @ np.abs(end - start) / 10.0) + 1)
    tips = np.array([tip_at(q) for q in steps])
    assert np.linalg.norm(np.diff(tips, axis=0), axis=1).max() <= 10.0


def exact_by_group(scene: Scene, q: np.ndarray) -> np.ndarray:
    """Per group of pairs, the least distance with every pair measured by coal here: group 0 the bodies against the
    solids (the base against no floor), group g the bodies' checked pairs whose lower link frame is g."""
    frames = UR5E.kin.link_frames(q)
    out = np.full(7, np.inf)
    for body in scene.bodies:
        for solid in scene.solids:
            if body.frame == 0 and isinstance(solid, Floor):
                continue
            out[0] = min(out[0], distance(body.shape, frames[body.frame], solid, np.eye(4))[0])
    for i, j in scene.pairs:
        one, other = scene.bodies[i], scene.bodies[j]
        g = min(one.frame, other.frame)
        out[g] = min(out[g], distance(one.shape, frames[one.frame], other.shape, frames[other.frame])[0])
    return out


@pytest.mark.parametrize("clearance", [5.0, 20.0, 60.0])
def test_each_step_stays_within_what_the_distance_allows(clearance):
    """Every step's travel bound, per group of pairs (the joints that move its two sides against each other), is at
    most max(d - c, 0) + c / 2 for the group's exact least distance d at the sample it starts from (measured here,
    every pair), what the sweep knew is never above it, and the samples run from the start to the end of the move."""
    rng = np.random.default_rng(7)
    scene = random_scene(rng)
    start = HOME + rng.uniform(-30.0, 30.0, 6)
    end = start + rng.uniform(-120.0, 120.0, 6)
    trail: list = []
    check_path(scene, joint_path(start, end), start, clearance, trail)
    weights = np.radians(reach(scene))
    per_group = np.array([[w if joint >= g else 0.0 for joint, w in enumerate(weights)] for g in range(7)])
    assert trail[0][0] == 0.0 and trail[-1][0] == 1.0
    for (_, q, known), (_, q_next, _) in itertools.pairwise(trail):
        exact = exact_by_group(scene, q)
        assert np.all(known <= exact + 1e-6)  # what the sweep knew is a lower bound
        step = per_group @ np.abs(q_next - q)
        allowed = np.maximum(exact - clearance, 0.0) + clearance / 2.0
        assert np.all(step[np.isfinite(exact)] <= allowed[np.isfinite(exact)] + 1e-9)
    assert len(trail) > 3  # the move is long enough to need steps


def brute_least(scene: Scene, joints: np.ndarray) -> float:
    """The least distance over every given configuration, every pair measured."""
    return min(found.distance for found in scene.nearest(joints) if found is not None)


def random_scene(rng: np.random.Generator) -> Scene:
    """Boxes of 5 to 150 mm placed about the tool's reach at home, some thin (a sheet or a rod), the floor."""
    solids = {"floor": Floor(-300.0)}
    for k in range(4):
        size = tuple(rng.choice([rng.uniform(0.5, 3.0), rng.uniform(20.0, 150.0)]) for _ in range(3))
        pose = np.eye(4)
        turn = rng.normal(size=3)
        pose[:3, :3] = poses_rot(turn)
        pose[:3, 3] = (rng.uniform(-650.0, 650.0), rng.uniform(-650.0, 650.0), rng.uniform(-100.0, 600.0))
        solids[f"box{k}"] = Box(size, pose)
    return Scene(UR5E, World(solids), tool=tool_cylinder(TOOL, 25.0))


def poses_rot(rotvec: np.ndarray) -> np.ndarray:
    angle = float(np.linalg.norm(rotvec))
    k = rotvec / angle
    cross = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.eye(3) + math.sin(angle) * cross + (1.0 - math.cos(angle)) * cross @ cross


@pytest.mark.parametrize("seed", range(12))
def test_against_brute_force_sampling(seed):
    """Random scenes and joint moves, against 3000 evenly spaced configurations each measured whole: the lower bound
    is never above any of them, the sampled least never below it, and a move that comes within half the clearance
    (contact included) anywhere is never passed."""
    rng = np.random.default_rng(seed)
    scene = random_scene(rng)
    start = HOME + rng.uniform(-60.0, 60.0, 6)
    end = start + rng.uniform(-90.0, 90.0, 6)
    result = check_path(scene, joint_path(start, end), start)
    fine = brute_least(scene, np.linspace(start, end, 3000))
    assert result.lower_bound <= fine + 1e-6
    assert result.lower_bound <= result.distance
    assert result.distance >= result.lower_bound
    if fine < CLEARANCE_MM / 2.0:
        assert not result.clear(CLEARANCE_MM)
    assert scene.nearest(np.array(result.joints)[None])[0].distance == pytest.approx(result.distance, abs=1e-6)


def test_brute_force_cases_include_contact_and_clear_moves():
    """The random cases above are not all one outcome: some moves touch a solid and some pass."""
    outcomes = set()
    for seed in range(12):
        rng = np.random.default_rng(seed)
        scene = random_scene(rng)
        start = HOME + rng.uniform(-60.0, 60.0, 6)
        end = start + rng.uniform(-90.0, 90.0, 6)
        outcomes.add(check_path(scene, joint_path(start, end), start).clear(CLEARANCE_MM))
    assert outcomes == {True, False}


def test_a_sheet_grazed_between_far_samples_is_found():
    """A 0.5 mm sheet that the tool's end only just reaches (5 mm deep) halfway along a long swing: far samples
    step widely, yet the move is not passed."""
    tip = tip_at(HOME)
    along = np.cross([0.0, 0.0, 1.0], tip)
    along /= np.linalg.norm(along)
    pose = np.eye(4)
    pose[:3, 0], pose[:3, 2] = along, (0.0, 0.0, 1.0)
    pose[:3, 1] = np.cross(pose[:3, 2], along)
    pose[:3, 3] = tip - (0.0, 0.0, 100.0 - 5.0)  # 200 mm high, its top 5 mm above the tool's end face
    scene = Scene(UR5E, World({"sheet": Box((0.5, 200.0, 200.0), pose)}), tool=tool_cylinder(TOOL, 25.0),
                  self_check=False)
    start, end = HOME.copy(), HOME.copy()
    start[0], end[0] = -150.0, 150.0
    result = check_path(scene, joint_path(start, end), start)
    assert not result.clear(CLEARANCE_MM) and result.other == "sheet"
    assert result.lower_bound < 0


def test_a_linear_move_follows_its_line():
    scene = Scene(UR5E, World({"floor": Floor(0.0)}), tool=tool_cylinder(TOOL, 25.0))
    start_pose = UR5E.kin.fk(HOME) @ TOOL
    end_pose = start_pose.copy()
    end_pose[2, 3] -= 400.0  # straight down from 337.9 mm: the tool's end face ends 62.1 mm below the floor
    path = linear_path(UR5E, TOOL, start_pose, end_pose)
    result = check_path(scene, path, HOME)
    assert result.body == "tool" and result.other == "floor"
    assert result.s == pytest.approx(1.0)
    assert result.distance == pytest.approx(end_pose[2, 3], abs=1e-6)  # the tool's flat end face, at the TCP, is lowest
    assert tip_at(result.joints) == pytest.approx(end_pose[:3, 3], abs=1e-6)


def test_ur5e_elbow_under_a_180_mm_pick_height():
    """Stations at +x, the catalogue's home facing -x: the IK nearest home (UR's qnear) folds the elbow down."""
    pick = np.eye(4)
    pick[:3, :3] = np.diag([1.0, -1.0, -1.0])  # tool pointing down
    pick[:3, 3] = (480.0, 0.0, 180.0)
    q, branch = solve.nearest(UR5E, solve.branches(UR5E, solve.flange_poses(pick, TOOL)), HOME)
    assert branch >= 0
    d1, a2 = UR5E.kin.d1, UR5E.kin.a2
    elbow_z = d1 + a2 * math.sin(math.radians(q[1]))  # the elbow's height, DH written out
    assert 55.0 < elbow_z < 75.0  # about 67 mm: under the 180 mm machine top
    scene = Scene(UR5E, World({"machine_top": Floor(180.0)}), tool=tool_cylinder(TOOL, 25.0))
    found = scene.nearest(q[None])[0]
    assert found.other == "machine_top" and found.body in ("upper_arm", "elbow", "forearm")
    assert found.distance < -100.0
    result = check_path(scene, joint_path(HOME, q), HOME)
    assert result.distance < 0 and not result.clear(CLEARANCE_MM)


def test_a_linear_move_turns_about_one_axis_at_an_even_rate():
    start_pose = UR5E.kin.fk(HOME) @ TOOL
    c, s = math.cos(math.radians(60.0)), math.sin(math.radians(60.0))
    end_pose = start_pose.copy()
    end_pose[:3, :3] = start_pose[:3, :3] @ np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    end_pose[:3, 3] += (100.0, 50.0, -80.0)
    path = linear_path(UR5E, TOOL, start_pose, end_pose)
    q = path(0.25, HOME)
    here = UR5E.kin.fk(q) @ TOOL
    c, s = math.cos(math.radians(15.0)), math.sin(math.radians(15.0))  # a quarter of 60 deg about the tool's z
    assert here[:3, :3] == pytest.approx(start_pose[:3, :3] @ np.array([[c, -s, 0.0], [s, c, 0.0], [0, 0, 1.0]]),
                                         abs=1e-9)
    assert here[:3, 3] == pytest.approx(start_pose[:3, 3] + 0.25 * np.array([100.0, 50.0, -80.0]), abs=1e-6)
    assert np.abs(q - HOME).max() < 30.0  # the solution near the joints before, not another branch


def test_a_linear_move_solved_in_one_batch_follows_the_chain():
    """The batch gives what solving each sample nearest the one before gives, also where axis 6 turns past 180 deg
    of where the move starts (the nearest to the start alone would take the other turn)."""
    start_pose = UR5E.kin.fk(HOME) @ TOOL
    c, s = math.cos(math.radians(170.0)), math.sin(math.radians(170.0))
    end_pose = start_pose.copy()
    end_pose[:3, :3] = start_pose[:3, :3] @ np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    end_pose[:3, 3] += (50.0, 0.0, -50.0)
    path = linear_path(UR5E, TOOL, start_pose, end_pose)
    fractions = np.linspace(0.0, 1.0, 41)
    chain, near = [], HOME
    for value in fractions:
        near, _ = solve.nearest(UR5E, solve.branches(UR5E, solve.flange_poses(path.poses([value])[0], TOOL)), near)
        chain.append(near)
    assert path.solve(fractions, HOME) == pytest.approx(np.array(chain), abs=1e-9)
    start = UR5E.kin.fk(HOME)
    assert abs(path.solve(fractions, HOME)[-1][5] - HOME[5]) > 150.0  # axis 6 turned with the tool, not back
    assert np.allclose(start, UR5E.kin.fk(path.solve(fractions[:1], HOME)[0]), atol=1e-6)


@pytest.mark.parametrize("seed", range(3))
def test_a_refined_grid_is_what_solving_the_whole_grid_gives(seed):
    """The grid of a linear move cut finer where a step travels too far solves each sample once: its joints are
    those of path.solve over the final grid, bit for bit (small moves too, solved pose by pose)."""
    rng = np.random.default_rng(seed)
    weights = np.radians(reach(Scene(UR5E, World({}), tool=tool_cylinder(TOOL, 25.0))))
    refined = 0
    for _ in range(12):
        q0 = HOME + rng.uniform(-40.0, 40.0, 6)
        start_pose = UR5E.kin.fk(q0) @ TOOL
        end_pose = start_pose.copy()
        end_pose[:3, 3] += rng.uniform(-400.0, 400.0, 3) * rng.choice([0.02, 1.0])
        turn = rng.uniform(-1.0, 1.0, 3)  # about a random axis, up to 120 deg: the joints far from linear in s
        angle = math.radians(rng.uniform(0.0, 120.0))
        x, y, z = turn / np.linalg.norm(turn)
        k = np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])
        end_pose[:3, :3] = start_pose[:3, :3] @ (np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * k @ k)
        path = linear_path(UR5E, TOOL, start_pose, end_pose)
        try:
            s, q = _grid(path, q0, weights, 10.0)
        except Unresolved:
            continue
        first = int(np.ceil(float(weights @ np.abs(path(1.0, q0) - q0)) / 10.0)) + 1
        refined += len(s) > first
        assert np.array_equal(q, path.solve(s, q0))
    assert refined >= 3
