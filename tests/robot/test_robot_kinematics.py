"""Closed-form arm kinematics: round trips on every branch, singularities, limits, and an independent ikpy model."""

from __future__ import annotations

import math

import numpy as np
import pytest
from support.robot_chains import VENDOR_CHAINS, ikpy_chain

from codegen.robot.kinematics import Kinematics, wrap_deg
from codegen.robot.opw import OPW
from codegen.robot.urdh import URDH

# Brandstoetter et al. 2014, worked parameter sets; offsets in this package's theta = s * q + offset (the
# paper and opw_kinematics write (0, -90, 0, 0, 0, 0) and (0, 0, -90, 0, 0, 0) for theta = s * q - offset)
KR6_R700 = OPW(25, -35, 0, 400, 315, 365, 80, (0, 90, 0, 0, 0, 0), (-1, 1, 1, -1, 1, -1))
IRB2400 = OPW(100, -135, 0, 615, 705, 755, 85, (0, 0, 90, 0, 0, 0), (1, 1, 1, 1, 1, 1))
UR5E = URDH(162.5, -425.0, -392.2, 133.3, 99.7, 99.6)  # UR's DH table, mm
UR10E = URDH(180.7, -612.7, -571.55, 174.15, 119.85, 116.55)
ARMS = {"KR 6 R700 sixx": KR6_R700, "IRB 2400/10": IRB2400, "UR5e": UR5E, "UR10e": UR10E}
# software limits (ros-industrial kuka_experimental kr6r700sixx_macro.xacro, abb irb2400_macro.xacro; UR +-360)
LIMITS = {
    "KR 6 R700 sixx": np.array([[-170, 170], [-190, 45], [-120, 156], [-185, 185], [-120, 120], [-350, 350]]),
    "IRB 2400/10": np.array([[-180, 180], [-100, 110], [-60, 65], [-200, 200], [-120, 120], [-400, 400]]),
    "UR5e": np.array([[-360, 360]] * 6),
    "UR10e": np.array([[-360, 360]] * 6),
}
POS_TOL_MM = 1e-9
ROT_TOL = 1e-12


def random_joints(name: str, count: int, seed: int = 0) -> np.ndarray:
    """Axis values within the limits, wrapped into (-180, 180] (what ik returns)."""
    limits = np.clip(LIMITS[name], -179.999, 180.0)
    rng = np.random.default_rng(seed)
    return rng.uniform(limits[:, 0], limits[:, 1], (count, 6))


def assert_round_trip(kin: Kinematics, flange2base: np.ndarray, pos_tol: float = POS_TOL_MM) -> np.ndarray:
    """ik's every complete row maps back to the pose; returns the solutions."""
    solutions = kin.ik(flange2base)
    complete = ~np.isnan(solutions).any(axis=-1)
    assert np.array_equal(complete, ~np.isnan(solutions).all(axis=-1)), "a row is partly NaN"
    assert complete.any(axis=-1).all(), "a reachable pose without solution"
    again = kin.fk(np.where(complete[..., None], solutions, 0.0))
    target = np.broadcast_to(flange2base[..., None, :, :], again.shape)
    assert np.abs(again - target)[..., :3, 3][complete].max() < pos_tol
    assert np.abs(again - target)[..., :3, :3][complete].max() < ROT_TOL + pos_tol * 1e-3
    return solutions


def closest_branch_error(solutions: np.ndarray, joints: np.ndarray) -> np.ndarray:
    """Per pose, the largest axis difference (deg, modulo 360) to the nearest solution row."""
    diff = np.abs(wrap_deg(solutions - joints[..., None, :])).max(axis=-1)
    return np.nanmin(diff, axis=-1)


def test_both_families_implement_the_protocol():
    for kin in ARMS.values():
        assert isinstance(kin, Kinematics)


@pytest.mark.parametrize("name", ARMS)
def test_batched_shapes(name):
    kin = ARMS[name]
    joints = random_joints(name, 6).reshape(2, 3, 6)
    poses = kin.fk(joints)
    assert poses.shape == (2, 3, 4, 4)
    assert kin.ik(poses).shape == (2, 3, 8, 6)
    assert kin.ik(poses[0, 0]).shape == (8, 6)
    assert kin.wrist_center(joints).shape == (2, 3, 3)
    np.testing.assert_allclose(kin.fk(joints[1, 2]), poses[1, 2], atol=1e-12)


def test_vendor_zero_positions():
    """Data-sheet geometry at the vendors' zero/home positions (fixes the offset sign convention)."""
    home = KR6_R700.fk(np.array([0, -90, 90, 0, 0, 0.0]))  # upper arm up, forearm and flange forward
    np.testing.assert_allclose(home[:3, 3], [25 + 365 + 80, 0, 400 + 315 + 35], atol=1e-9)
    np.testing.assert_allclose(home[:3, 2], [1, 0, 0], atol=1e-12)
    home = IRB2400.fk(np.zeros(6))
    np.testing.assert_allclose(home[:3, 3], [100 + 755 + 85, 0, 615 + 705 + 135], atol=1e-9)
    np.testing.assert_allclose(home[:3, 2], [1, 0, 0], atol=1e-12)
    zero = UR5E.fk(np.zeros(6))  # stretched along base -x
    np.testing.assert_allclose(zero[:3, 3], [-425.0 - 392.2, -(133.3 + 99.6), 162.5 - 99.7], atol=1e-9)


@pytest.mark.parametrize("name", ARMS)
def test_ik_round_trip_on_every_branch_and_finds_the_joints(name):
    kin = ARMS[name]
    joints = random_joints(name, 400, seed=1)
    solutions = assert_round_trip(kin, kin.fk(joints))
    assert (np.abs(solutions[~np.isnan(solutions)]) <= 180.0).all()
    assert closest_branch_error(solutions, joints).max() < 1e-6


@pytest.mark.parametrize("name", ["KR 6 R700 sixx", "IRB 2400/10"])
def test_opw_branch_order(name):
    """index = 4 shoulder + 2 elbow + wrist, each bit as documented on OPW."""
    kin = ARMS[name]
    solutions = kin.ik(kin.fk(random_joints(name, 200, seed=2)))
    index = np.broadcast_to(np.arange(8), solutions.shape[:-1])
    ok = ~np.isnan(solutions).any(axis=-1)
    q, index = solutions[ok], index[ok]
    x1, side, theta5 = kin.wrist_x_axis1(q), kin.elbow_side(q), kin.theta(q)[:, 4]
    clear = (np.abs(x1) > 1e-6) & (np.abs(side) > 1e-9) & (np.abs(np.sin(theta5)) > 1e-9)
    assert clear.mean() > 0.99
    assert np.array_equal((x1 < 0)[clear], (index >> 2 & 1)[clear] == 1)
    assert np.array_equal((side < 0)[clear], (index >> 1 & 1)[clear] == 1)
    assert np.array_equal((theta5 < 0)[clear], (index & 1)[clear] == 1)


@pytest.mark.parametrize("name", ["UR5e", "UR10e"])
def test_ur_branch_order(name):
    kin = ARMS[name]
    solutions = kin.ik(kin.fk(random_joints(name, 200, seed=3)))
    index = np.broadcast_to(np.arange(8), solutions.shape[:-1])
    ok = ~np.isnan(solutions).any(axis=-1)
    q, index = solutions[ok], index[ok]
    q1 = np.radians(q[:, 0])
    p5 = kin.wrist_center(q)
    x1 = p5[:, 0] * np.cos(q1) + p5[:, 1] * np.sin(q1)  # p5 along the x axis of joint 1's frame
    clear = (np.abs(x1) > 1e-6) & (np.abs(q[:, 2]) > 1e-9) & (np.abs(q[:, 4]) > 1e-9)
    assert np.array_equal((x1 > 0)[clear], (index >> 2 & 1)[clear] == 1)
    assert np.array_equal((q[:, 2] < 0)[clear], (index >> 1 & 1)[clear] == 1)
    assert np.array_equal((q[:, 4] < 0)[clear], (index & 1)[clear] == 1)


@pytest.mark.parametrize("name", ARMS)
@pytest.mark.parametrize("theta5_deg", [0.0, 1e-6, -1e-6, 1e-4, -1e-3, 1e-2])
def test_wrist_singularity(name, theta5_deg):
    kin = ARMS[name]
    joints = random_joints(name, 50, seed=4)
    joints[:, 4] = theta5_deg  # q5 = theta5 for all four arms (sign +1, offset 0)
    solutions = assert_round_trip(kin, kin.fk(joints))
    if theta5_deg == 0.0:  # convention on singular rows of wrist branch 0: q4 = 0 (OPW), q6 = 0 (UR) where
        branch0 = solutions[..., ::2, :]  # q6 = 0 leaves joint 4 within the arm's reach
        singular = np.abs(np.sin(np.radians(branch0[..., 4]))) < 1e-12
        assert singular.sum() >= len(joints)  # at least the original's arm branch
        if isinstance(kin, OPW):
            assert np.all(branch0[..., 3][singular] == 0.0)
        else:
            assert np.mean(branch0[..., 5][singular] == 0.0) > 0.5
    else:  # q4 and q6 are conditioned by 1 / sin(theta5)
        tolerance = 1e-6 + math.degrees(1e-12 / math.sin(math.radians(abs(theta5_deg))))
        assert closest_branch_error(solutions, joints).max() < tolerance


def opw_on_axis1(kin: OPW, beta: np.ndarray, q1: np.ndarray) -> np.ndarray:
    """Joints that put the wrist centre on axis 1 (b = 0): a1 + c2 sin t2 + k sin(t2 + beta) = 0."""
    k = math.hypot(kin.a2, kin.c3)
    big_a, big_b = kin.c2 + k * np.cos(beta), k * np.sin(beta)
    theta2 = np.arcsin(-kin.a1 / np.hypot(big_a, big_b)) - np.arctan2(big_b, big_a)
    theta3 = beta - kin.psi3
    q = np.zeros((len(beta), 6))
    q[:, 0] = q1
    q[:, 1] = kin.signs[1] * (np.degrees(theta2) - kin.offsets_deg[1])
    q[:, 2] = kin.signs[2] * (np.degrees(theta3) - kin.offsets_deg[2])
    q[:, 3:] = (30.0, 40.0, 50.0)
    return wrap_deg(q)


@pytest.mark.parametrize("name", ["KR 6 R700 sixx", "IRB 2400/10"])
def test_opw_shoulder_singularity(name):
    kin = ARMS[name]
    beta = np.radians(np.linspace(20, 160, 15))
    joints = opw_on_axis1(kin, beta, np.full(15, 37.0))
    assert np.abs(kin.wrist_center(joints)[:, :2]).max() < 1e-9
    solutions = assert_round_trip(kin, kin.fk(joints))
    front, back = solutions[:, :4, 0], solutions[:, 4:, 0]
    assert np.all(front[~np.isnan(front)] == 0.0)  # convention: q1 = 0
    assert np.allclose(np.abs(back[~np.isnan(back)]), 180.0)
    # just off the axis the arm plane is determined again and ik finds the joints
    near = joints.copy()
    for offset_deg in (1e-3, 1e-1):
        near[:, 1] = joints[:, 1] + offset_deg
        solutions = assert_round_trip(kin, kin.fk(near))
        assert closest_branch_error(solutions, near).max() < 1e-6


def test_ur_shoulder_singularity():
    """p5 on the cylinder |p5_xy| = d4 (upper arm and forearm straight up, wrist 1 level): q1 roots meet."""
    for kin in (UR5E, UR10E):
        joints = np.array([[q1, -90.0, 0.0, -90.0 + d, 50.0, 20.0] for q1 in (-100.0, 0.0, 35.0) for d in (0, 1e-5)])
        solutions = assert_round_trip(kin, kin.fk(joints))
        assert closest_branch_error(solutions, joints).max() < 1e-3


@pytest.mark.parametrize("name", ARMS)
@pytest.mark.parametrize("epsilon", [0.0, 1e-9, -1e-7, 1e-5, -1e-3])
def test_elbow_near_stretched(name, epsilon):
    kin = ARMS[name]
    joints = random_joints(name, 50, seed=5)
    if isinstance(kin, OPW):  # theta3 + psi3 = epsilon (rad)
        joints[:, 2] = kin.joints_from_theta_deg(3, math.degrees(epsilon - kin.psi3))
    else:
        joints[:, 2] = math.degrees(epsilon)
    solutions = assert_round_trip(kin, kin.fk(joints))
    assert closest_branch_error(solutions, joints).max() < 1e-4


@pytest.mark.parametrize("name", ARMS)
def test_near_joint_limits(name):
    kin = ARMS[name]
    limits = np.clip(LIMITS[name], -179.999, 180.0)
    joints = random_joints(name, 60, seed=6)
    for axis in range(6):
        joints[10 * axis : 10 * axis + 5, axis] = limits[axis, 0] + 1e-9
        joints[10 * axis + 5 : 10 * axis + 10, axis] = limits[axis, 1] - 1e-9
    solutions = assert_round_trip(kin, kin.fk(joints))
    # UR's limits put q3 and q5 at +-180 deg, the folded elbow and the wrist singularity: ik finds an
    # equivalent solution there (checked above), the same joints only where the pose is well conditioned
    if isinstance(kin, OPW):
        wrist, elbow = np.sin(kin.theta(joints)[:, 4]), kin.elbow_side(joints)
    else:
        wrist, elbow = np.sin(np.radians(joints[:, 4])), np.sin(np.radians(joints[:, 2]))
    conditioned = (np.abs(wrist) > 1e-3) & (np.abs(elbow) > 1e-3)
    assert conditioned.sum() >= 40
    assert closest_branch_error(solutions, joints)[conditioned].max() < 1e-6


@pytest.mark.parametrize("name", ARMS)
def test_unreachable_gives_nan_rows(name):
    kin = ARMS[name]
    pose = np.eye(4)
    pose[:3, 3] = (5000.0, 0.0, 500.0)
    assert np.isnan(kin.ik(pose)).all()
    batch = np.stack([pose, kin.fk(random_joints(name, 1, seed=7)[0])])
    solutions = kin.ik(batch)
    assert np.isnan(solutions[0]).all() and not np.isnan(solutions[1]).all()


@pytest.mark.parametrize("name", ARMS)
def test_fk_agrees_with_ikpy_vendor_model(name):
    kin = ARMS[name]
    chain, active = ikpy_chain(VENDOR_CHAINS[name])
    joints = random_joints(name, 40, seed=8)
    joints[0] = 0.0
    for q in joints:
        angles = np.zeros(len(active))
        angles[active] = np.radians(q)
        expected = chain.forward_kinematics(angles)
        got = kin.fk(q)
        scale = max(1.0, float(np.linalg.norm(expected[:3, 3])))
        assert np.abs(got[:3, 3] - expected[:3, 3]).max() <= 1e-9 * scale
        assert np.abs(got[:3, :3] - expected[:3, :3]).max() <= 1e-9
