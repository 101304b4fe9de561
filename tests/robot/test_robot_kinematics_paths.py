"""ik's two paths agree: pose by pose on Python floats (up to SMALL_BATCH poses, what the interpreter asks for)
and batched in numpy. Every branch of random poses, singular and near-singular ones, unreachable and non-finite
poses, on every catalogue arm and two OPW arms with a shoulder offset b."""

from __future__ import annotations

import numpy as np
import pytest

from codegen.robot.arms import catalogue
from codegen.robot.kinematics import CHUNK, SMALL_BATCH
from codegen.robot.opw import OPW
from codegen.robot.urdh import URDH

ARMS = {name: arm.kin for name, arm in catalogue().items()}
ARMS["OPW b = 30"] = OPW(100, -135, 30, 615, 705, 755, 85, (0, 0, 90, 0, 0, 0), (1, 1, 1, 1, 1, 1))
ARMS["OPW b = -40, KUKA signs"] = OPW(25, -35, -40, 400, 315, 365, 80, (0, 90, 0, 0, 0, 0), (-1, 1, 1, -1, 1, -1))
CONDITIONED = 1e-2  # sin of the wrist, elbow and shoulder angles above this: the rows must agree to AGREE_DEG
AGREE_DEG = 1e-10  # observed at most ~1e-11: ulps of math and numpy's own atan2, acos, hypot (and of BLAS)
POS_TOL_MM = 1e-9


def special_joints(kin, rng: np.random.Generator, count: int) -> np.ndarray:
    """Random axis values, a third of them at or near the wrist, elbow and shoulder singularities."""
    q = rng.uniform(-180.0, 180.0, (count, 6))
    third = count // 3
    wrist = rng.choice([0.0, 180.0, 1e-13, -1e-10, 1e-6, -1e-3], third)
    if isinstance(kin, OPW):
        q[:third, 4] = [kin.joints_from_theta_deg(5, w) for w in wrist]
        q[third : 2 * third, 2] = kin.stretched_q3_deg + rng.choice([0.0, 180.0, 1e-9, -1e-7], third)
    else:
        q[:third, 4] = wrist
        q[third : 2 * third, 2] = rng.choice([0.0, 180.0, 1e-9, -1e-7], third)
        q[2 * third : 2 * third + 10, 1:4] = (-90.0, 0.0, -90.0)  # p5 on the cylinder |p5_xy| = d4
    return np.round(q, rng.integers(0, 4))  # round values: exact zeros in the matrices


def special_poses(kin, seed: int, count: int = 600) -> np.ndarray:
    rng = np.random.default_rng(seed)
    poses = kin.fk(special_joints(kin, rng, count))
    far = np.eye(4)
    far[:3, 3] = (1e5, 0.0, 0.0)
    on_axis = np.eye(4)
    on_axis[:3, 3] = (0.0, 0.0, 700.0)  # wrist centre on axis 1 (OPW); p5 on the base z axis (UR)
    return np.concatenate([poses, [far, on_axis]])


def conditioning(kin, solutions: np.ndarray) -> np.ndarray:
    """Per solution row the smallest |sin| of the wrist, elbow and shoulder angles (0 for NaN rows)."""
    q = np.where(np.isnan(solutions), 0.0, solutions)
    if isinstance(kin, OPW):
        centre = kin.wrist_center(q)
        shoulder = np.minimum(np.hypot(centre[..., 0], centre[..., 1]), 1.0)  # mm from axis 1, up to 1
        wrist, elbow = np.sin(kin.theta(q)[..., 4]), kin.elbow_side(q)
    else:
        p5 = kin.wrist_center(q)
        shoulder = np.sqrt(np.clip(1.0 - (kin.d4 / np.hypot(p5[..., 0], p5[..., 1])) ** 2, 0.0, 1.0))
        wrist, elbow = np.sin(np.radians(q[..., 4])), np.sin(np.radians(q[..., 2]))
    return np.where(np.isnan(solutions).any(axis=-1), 0.0, np.minimum.reduce([np.abs(wrist), np.abs(elbow), shoulder]))


def assert_solves(kin, poses: np.ndarray, solutions: np.ndarray) -> None:
    complete = ~np.isnan(solutions).any(axis=-1)
    again = kin.fk(np.where(complete[..., None], solutions, 0.0))
    target = np.broadcast_to(poses[..., None, :, :], again.shape)
    assert np.abs(again - target)[..., :3, 3][complete].max() < POS_TOL_MM
    assert np.abs(again - target)[..., :3, :3][complete].max() < 1e-11


@pytest.mark.parametrize("name", ARMS)
@pytest.mark.parametrize("seed", [0, 1])
def test_pose_by_pose_agrees_with_batched(name, seed):
    kin = ARMS[name]
    poses = special_poses(kin, seed)
    batched = kin._ik(poses, scalar=False)
    by_pose = np.stack([kin._ik(pose, scalar=True) for pose in poses])
    taken = [kin._theta_floats(pose[None]) is not None for pose in poses]
    if isinstance(kin, OPW):
        assert all(taken)
    else:  # UR: only where q6 = 0 leaves joint 4 out of reach (_singular_q6) or p5 lies on the base z axis
        assert np.mean(taken) > 0.9
    assert np.array_equal(np.isnan(by_pose), np.isnan(batched))  # the same branches, whole or absent
    assert np.isnan(by_pose[-2]).all()  # unreachable
    difference = np.abs(by_pose - batched)
    difference = np.minimum(difference, 360.0 - difference).max(axis=-1)  # per row, modulo a turn
    conditioned = conditioning(kin, batched) > CONDITIONED
    assert conditioned.sum() > 0.5 * len(poses) * 8 * (~np.isnan(batched).any(axis=-1)).mean()
    assert difference[conditioned].max() < AGREE_DEG
    # elsewhere the angles are only determined to ulp / sin (the singularity): both solve the pose
    assert_solves(kin, poses, by_pose)


@pytest.mark.parametrize("name", ["KR 10 R1100 sixx", "IRB 1200-5/0.9", "OPW b = 30", "UR10e", "UR5e"])
def test_singular_conventions_pose_by_pose(name):
    """At the wrist singularity the pose-by-pose path keeps the documented choice (q4 = 0 on OPW wrist-0 rows,
    q6 = 0 on UR where that leaves joint 4 within reach), as the batched path does."""
    kin = ARMS[name]
    joints = np.random.default_rng(4).uniform(-170.0, 170.0, (40, 6))
    joints[:, 4] = kin.joints_from_theta_deg(5, 0.0) if isinstance(kin, OPW) else 0.0
    poses = kin.fk(joints)
    by_pose = np.stack([kin._ik(pose, scalar=True) for pose in poses])
    batched = kin._ik(poses, scalar=False)
    assert np.array_equal(np.isnan(by_pose), np.isnan(batched))
    branch0, batch0 = by_pose[:, ::2], batched[:, ::2]
    axis = 3 if isinstance(kin, OPW) else 5
    zero = batch0[..., axis] == 0.0
    assert zero.sum() >= len(joints) // 2
    assert np.all(branch0[..., axis][zero] == 0.0)
    assert_solves(kin, poses, by_pose)


@pytest.mark.parametrize("name", ["KR 10 R1100 sixx", "OPW b = 30", "UR10e"])
def test_non_finite_poses(name):
    """NaN or inf anywhere: the same NaN rows on both paths, and no exception from the math module."""
    kin = ARMS[name]
    pose = kin.fk(np.array([10.0, -70.0, 80.0, 20.0, 30.0, 40.0]))
    for value in (np.nan, np.inf, -np.inf):
        for row in range(3):
            for column in range(4):
                bad = pose.copy()
                bad[row, column] = value
                by_pose, batched = kin._ik(bad, scalar=True), kin._ik(bad, scalar=False)
                assert np.array_equal(np.isnan(by_pose), np.isnan(batched))
                np.testing.assert_allclose(by_pose, batched, atol=AGREE_DEG)


def test_ik_takes_the_path_by_batch_size():
    """ik on up to SMALL_BATCH poses equals the pose-by-pose path, beyond it the batched path (any shape)."""
    for kin in (ARMS["KR 10 R1100 sixx"], ARMS["UR10e"]):
        joints = np.random.default_rng(5).uniform(-170.0, 170.0, (SMALL_BATCH + 1, 6))
        poses = kin.fk(joints)
        assert np.array_equal(kin.ik(poses[0]), kin._ik(poses[0], scalar=True), equal_nan=True)
        small = poses[:SMALL_BATCH].reshape(2, SMALL_BATCH // 2, 4, 4)
        assert kin.ik(small).shape == (2, SMALL_BATCH // 2, 8, 6)
        assert np.array_equal(kin.ik(small), kin._ik(small, scalar=True), equal_nan=True)
        assert np.array_equal(kin.ik(poses), kin._ik(poses, scalar=False), equal_nan=True)
        assert kin.ik(poses[:0]).shape == (0, 8, 6)
        assert np.array_equal(kin.ik(poses[0].tolist()), kin.ik(poses[0]), equal_nan=True)
    assert isinstance(ARMS["UR10e"], URDH)


def test_chunks_change_nothing():
    """Batches beyond CHUNK poses run in chunks: the same numbers as any other split of the batch."""
    for kin in (ARMS["KR 10 R1100 sixx"], ARMS["OPW b = 30"], ARMS["UR10e"]):
        joints = np.random.default_rng(6).uniform(-180.0, 180.0, (CHUNK + 10, 6))
        poses = kin.fk(joints)
        pieces = range(0, len(joints), 1000)
        assert np.array_equal(poses, np.concatenate([kin.fk(joints[i : i + 1000]) for i in pieces]))
        assert np.array_equal(
            kin.wrist_center(joints), np.concatenate([kin.wrist_center(joints[i : i + 1000]) for i in pieces])
        )
        solutions = kin._ik(poses, scalar=False)
        by_piece = np.concatenate([kin._ik(poses[i : i + 1000], scalar=False) for i in pieces])
        assert np.array_equal(solutions, by_piece, equal_nan=True)
