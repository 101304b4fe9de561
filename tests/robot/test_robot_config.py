"""Vendor configurations: ABB confdata, KUKA Status/Turn, turn variants and choosing a solution by them."""

from __future__ import annotations

import numpy as np
import pytest
from support.robot_select import nearest, select_abb, select_kuka, turn_variants

from codegen.robot import solve
from codegen.robot.arms import Arm
from codegen.robot.config import abb_confdata, abb_quadrant, by_confdata, by_status_turn, kuka_status, kuka_turn
from codegen.robot.opw import OPW
from codegen.robot.urdh import URDH

KR6_R700 = OPW(25, -35, 0, 400, 315, 365, 80, (0, 90, 0, 0, 0, 0), (-1, 1, 1, -1, 1, -1))
IRB2400 = OPW(100, -135, 0, 615, 705, 755, 85, (0, 0, 90, 0, 0, 0), (1, 1, 1, 1, 1, 1))
UR5E = URDH(162.5, -425.0, -392.2, 133.3, 99.7, 99.6)
KR6_LIMITS = np.array([[-170, 170], [-190, 45], [-120, 156], [-185, 185], [-120, 120], [-350, 350]], dtype=float)
IRB2400_LIMITS = np.array([[-180, 180], [-100, 110], [-60, 65], [-200, 200], [-120, 120], [-400, 400]], dtype=float)
UR_LIMITS = np.array([[-360, 360]] * 6, dtype=float)


def q(*values: float) -> np.ndarray:
    return np.array(values, dtype=float)


# ------------------------------------------------------------------------------------------ ABB confdata


def test_abb_quadrants_from_the_manual():
    """Quadrant 0 is 0..90 deg, 1 is 90..180, -1 is 0..-90 (RAPID data types, confdata)."""
    assert abb_confdata(IRB2400, q(-45, 0, 0, 0, 30, 0))[0] == -1
    assert abb_confdata(IRB2400, q(100, 0, 0, 0, 30, 0))[0] == 1
    assert abb_confdata(IRB2400, q(45, 0, 0, 0, 30, 0))[0] == 0
    assert abb_confdata(IRB2400, q(-100, 0, 0, 0, 30, 0))[0] == -2
    assert tuple(abb_confdata(IRB2400, q(0, 0, 0, 370, 30, -370))[:3]) == (0, 4, -5)
    assert abb_quadrant(q(-90.0, -0.1, 0, 89.9, 90, 180, 359)).tolist() == [-1, -1, 0, 0, 1, 2, 3]


def test_abb_cfx_hand_cases():
    """cfx = 4 (wrist centre behind axis 1) + 2 (behind the lower arm) + 1 (axis 5 negative)."""
    assert tuple(abb_confdata(IRB2400, q(0, 0, 0, 0, 30, 0))) == (0, 0, 0, 0)  # calibration pose, wrist bent
    assert abb_confdata(IRB2400, q(0, 0, 0, 0, -30, 0))[3] == 1
    # lower arm straight back, forearm up: wrist centre 740 mm behind axis 1, in front of the lower arm
    assert abb_confdata(IRB2400, q(0, -90, 0, 0, 30, 0))[3] == 4
    assert abb_confdata(IRB2400, q(0, -90, 0, 0, -30, 0))[3] == 5
    # lower arm 60 deg forward, forearm folded down past the lower arm's line: wrist centre behind it
    assert abb_confdata(IRB2400, q(0, 60, -150, 0, 30, 0))[3] == 2
    assert abb_confdata(IRB2400, q(180, -90, 0, 0, -30, 0))[3] == 5  # axis 1 turns with the arm


def test_abb_confdata_is_batched():
    joints = np.zeros((3, 8, 6))
    joints[..., 4] = 30.0
    assert abb_confdata(IRB2400, joints).shape == (3, 8, 4)


# --------------------------------------------------------------------------------------- KUKA Status/Turn


def test_kuka_turn_bits():
    assert kuka_turn(q(10, 20, 30, 40, 50, 60)) == 0  # every axis positive
    assert kuka_turn(q(0, -90, 90, 0, 0, 0)) == 2  # only A2 negative
    assert kuka_turn(q(-1, 0, -1, 0, 0, -1)) == 1 + 4 + 32
    assert kuka_turn(q(-0.001, -5, -5, -5, -5, -5)) == 63
    assert kuka_turn(np.zeros((4, 6))).tolist() == [0, 0, 0, 0]


def test_kuka_status_hand_cases():
    # all axes positive with the wrist in front (basic area), A3 above the stretched angle: S = 'B010', T = 0
    assert kuka_status(KR6_R700, q(10, 20, 30, 40, 50, 60)) == 2
    assert kuka_status(KR6_R700, q(0, -90, 90, 0, 0, 0)) == 2  # mechanical zero/home posture
    assert kuka_status(KR6_R700, q(0, -90, 90, 0, -30, 0)) & 4  # A5 negative: bit 2
    assert kuka_status(KR6_R700, q(0, -90, 90, 0, -30, 0)) == 6
    # lower arm pointing back horizontally, forearm up: wrist point 325 mm behind A1, overhead area (bit 0)
    assert kuka_status(KR6_R700, q(0, -180, 90, 0, 30, 0)) == 3


def test_kuka_status_bit1_turns_at_the_stretched_angle():
    """phi = atan(35 / 365) = 5.48 deg for the KR AGILUS (A4 runs 35 mm above A3); 0 where A3 and A4 meet."""
    assert abs(KR6_R700.stretched_q3_deg - 5.4774) < 1e-3
    assert kuka_status(KR6_R700, q(0, -90, 5, 0, 30, 0)) & 2 == 0
    assert kuka_status(KR6_R700, q(0, -90, 6, 0, 30, 0)) & 2 == 2
    intersecting = OPW(25, 0, 0, 400, 315, 365, 80, (0, 90, 0, 0, 0, 0), (-1, 1, 1, -1, 1, -1))
    assert intersecting.stretched_q3_deg == 0.0
    assert kuka_status(intersecting, q(0, -90, -0.001, 0, 30, 0)) & 2 == 0
    assert kuka_status(intersecting, q(0, -90, 0.0, 0, 30, 0)) & 2 == 2


def test_kuka_status_bit2_ranges():
    """0 for 0 <= A5 < 180 or A5 < -180, 1 for -180 <= A5 < 0 or A5 >= 180."""
    for a5, bit in ((0.0, 0), (179.9, 0), (-190.0, 0), (-180.0, 4), (-0.1, 4), (180.0, 4), (200.0, 4)):
        assert kuka_status(KR6_R700, q(0, -90, 90, 0, a5, 0)) & 4 == bit, a5


def test_the_branch_index_is_the_configuration():
    """OPW's ik order: cfx is the branch index (ABB); Status bit 0 = shoulder, bit 2 = wrist and bit 1 the
    complement of elbow (KUKA): a configuration picks one ik row."""
    for kin, limits, seed in ((IRB2400, IRB2400_LIMITS, 20), (KR6_R700, KR6_LIMITS, 21)):
        joints = random_within(limits, 100, seed)
        joints = joints[well_conditioned(kin, joints)]
        solutions = kin.ik(kin.fk(joints))
        index = np.broadcast_to(np.arange(8), solutions.shape[:-1])
        ok = ~np.isnan(solutions).any(axis=-1)
        if kin is IRB2400:
            assert np.array_equal(abb_confdata(kin, solutions[ok])[:, 3], index[ok])
        else:
            expected = (index >> 2 & 1) | ((1 - (index >> 1 & 1)) << 1) | ((index & 1) << 2)
            assert np.array_equal(kuka_status(kin, solutions[ok]), expected[ok])


# -------------------------------------------------------------------------------------------- turn variants


def test_turn_variants_add_the_turns_within_the_limits():
    rows = turn_variants(q(0, -90, 90, 178, 30, 10), KR6_LIMITS)
    assert rows.tolist() == [
        [0, -90, 90, 178, 30, 10],
        [0, -90, 90, 178, 30, -350],
        [0, -90, 90, -182, 30, 10],
        [0, -90, 90, -182, 30, -350],
    ]
    # A2 at 170 is outside [-190, 45]; its turn -190 is inside
    assert turn_variants(q(0, 170, 90, 0, 30, 175), KR6_LIMITS)[:, 1].tolist() == [-190, -190]
    assert len(turn_variants(q(0, 0, 0, 0, 0, 0), UR_LIMITS)) == 3**6
    assert len(turn_variants(np.full((8, 6), np.nan), UR_LIMITS)) == 0
    assert len(turn_variants(q(175, 0, 0, 0, 0, 0), KR6_LIMITS)) == 0  # A1 beyond +-170 either way


# ------------------------------------------------------------------------------- selection round trips


def well_conditioned(kin: OPW, joints: np.ndarray) -> np.ndarray:
    """Away from the three singularities, where ik reproduces joints to 1e-9 deg."""
    return (
        (np.abs(np.sin(kin.theta(joints)[:, 4])) > 0.02)
        & (np.abs(kin.elbow_side(joints)) > 0.02)
        & (np.abs(kin.wrist_x_axis1(joints)) > 1.0)
    )


def random_within(limits: np.ndarray, count: int, seed: int) -> np.ndarray:
    return np.random.default_rng(seed).uniform(limits[:, 0], limits[:, 1], (count, 6))


def test_select_abb_returns_the_joints_of_the_confdata():
    joints = random_within(IRB2400_LIMITS, 300, seed=10)
    joints = joints[well_conditioned(IRB2400, joints)]
    assert len(joints) > 200
    solutions = IRB2400.ik(IRB2400.fk(joints))
    confs = abb_confdata(IRB2400, joints)
    for truth, sols, conf in zip(joints, solutions, confs, strict=True):
        chosen = select_abb(IRB2400, sols, conf, IRB2400_LIMITS)
        assert chosen is not None
        assert np.abs(chosen - truth).max() < 1e-9


def test_select_kuka_returns_the_joints_of_status_and_turn():
    joints = random_within(KR6_LIMITS, 300, seed=11)
    joints = joints[well_conditioned(KR6_R700, joints)]
    assert len(joints) > 200
    solutions = KR6_R700.ik(KR6_R700.fk(joints))
    for truth, sols in zip(joints, solutions, strict=True):
        chosen = select_kuka(KR6_R700, sols, kuka_status(KR6_R700, truth), kuka_turn(truth), KR6_LIMITS)
        assert chosen is not None
        assert np.abs(chosen - truth).max() < 1e-9


@pytest.mark.parametrize(("kin", "limits"), [(UR5E, UR_LIMITS), (KR6_R700, KR6_LIMITS), (IRB2400, IRB2400_LIMITS)])
def test_nearest_returns_the_joints_near_the_reference(kin, limits):
    rng = np.random.default_rng(12)
    joints = random_within(limits, 200, seed=13)
    if isinstance(kin, OPW):
        joints = joints[well_conditioned(kin, joints)]
    else:  # away from UR's wrist and elbow singularities
        joints = joints[
            (np.abs(np.sin(np.radians(joints[:, 4]))) > 0.02) & (np.abs(np.sin(np.radians(joints[:, 2]))) > 0.02)
        ]
    solutions = kin.ik(kin.fk(joints))
    for metric in ("euclidean", "max"):
        for truth, sols in zip(joints, solutions, strict=True):
            reference = truth + rng.uniform(-1.0, 1.0, 6)
            chosen = nearest(sols, reference, limits, metric=metric)
            assert chosen is not None
            assert np.abs(chosen - truth).max() < 1e-9


def test_selection_returns_none_when_nothing_matches():
    truth = q(10, -80, 100, 20, 40, 30)
    solutions = KR6_R700.ik(KR6_R700.fk(truth))
    status = kuka_status(KR6_R700, truth)
    assert select_kuka(KR6_R700, solutions, status, kuka_turn(truth), KR6_LIMITS) is not None
    assert select_kuka(KR6_R700, solutions, status, kuka_turn(truth) | 1, KR6_LIMITS) is None  # A1 -350: no
    truth = q(10, 20, 30, 20, 40, 30)
    solutions = IRB2400.ik(IRB2400.fk(truth))
    conf = abb_confdata(IRB2400, truth)
    assert select_abb(IRB2400, solutions, conf, IRB2400_LIMITS) is not None
    assert select_abb(IRB2400, solutions, (3, *conf[1:]), IRB2400_LIMITS) is None  # axis 1 in 270..360
    unreachable = np.full((8, 6), np.nan)
    assert nearest(unreachable, truth, KR6_LIMITS) is None
    assert select_abb(IRB2400, unreachable, conf, IRB2400_LIMITS) is None
    with pytest.raises(ValueError, match="metric"):
        nearest(solutions, truth, IRB2400_LIMITS, metric="manhattan")


def _arm(kin, limits, family="opw") -> Arm:
    return Arm("test arm", "test", family, kin, tuple(map(tuple, limits)), (0.0,) * 6)


def test_the_controllers_rules_agree_with_enumerating_every_turn():
    """codegen's batched selection (each axis shifted to its turn) against the enumeration above."""
    rng = np.random.default_rng(21)
    checks = 0
    arms = ((KR6_R700, KR6_LIMITS, "opw"), (IRB2400, IRB2400_LIMITS, "opw"), (UR5E, UR_LIMITS, "ur"))
    for kin, limits, family in arms:
        arm = _arm(kin, limits, family)
        truth = rng.uniform(limits[:, 0], limits[:, 1], (60, 6))
        solutions = kin.ik(kin.fk(truth))
        for joints, sols in zip(truth, solutions, strict=True):
            reference = joints + rng.normal(0, 3, 6)
            got, _ = solve.nearest(arm, sols, reference)
            want = nearest(sols, reference, limits)
            assert (want is None) == np.isnan(got).any()
            if want is not None:
                assert np.linalg.norm(got - reference) <= np.linalg.norm(want - reference) + 1e-9
            if family != "opw":
                continue
            if kin is IRB2400:
                conf = abb_confdata(kin, joints)
                got, _ = by_confdata(arm, sols, conf)
                want = select_abb(kin, sols, conf, limits)
            else:
                got, _ = by_status_turn(arm, sols, kuka_status(kin, joints), kuka_turn(joints))
                want = select_kuka(kin, sols, kuka_status(kin, joints), kuka_turn(joints), limits)
            assert want is not None and np.abs(got - want).max() < 1e-6, (joints, got, want)
            assert np.abs(got - joints).max() < 1e-6
            checks += 1
    assert checks == 120


def test_one_pose_selection_is_the_batched_one():
    """solve.nearest on one pose (Python floats) gives what the batched numpy path gives for it: the same
    joints (signed zeros too) and branch, for arms whose limits span more and less than a turn, with
    branches missing (NaN), axes on a limit (the IK's rounding puts them just over it), a turn away,
    equally near solutions, and a reference that is not a number."""
    rng = np.random.default_rng(16)
    arms = ((UR5E, UR_LIMITS, "ur"), (KR6_R700, KR6_LIMITS, "opw"), (IRB2400, IRB2400_LIMITS, "opw"))
    for kin, limits, family in arms:
        arm = _arm(kin, limits, family)
        truth = rng.uniform(limits[:, 0], limits[:, 1], (300, 6))
        rows = np.arange(0, 300, 3)
        axis = rng.integers(0, 6, rows.size)
        truth[rows, axis] = limits[axis, rng.integers(0, 2, rows.size)]  # on a limit
        solutions = kin.ik(kin.fk(truth))
        solutions[::7, 3:5] = np.nan  # branches without a solution
        solutions[2::9] = solutions[2::9, :1]  # every branch the same: the first is chosen
        solutions[4::11, :, 0] = -0.0
        references = truth + rng.normal(0, 3, truth.shape)
        references[1::5] += rng.normal(0, 90, (60, 6))
        references[::5] += 360.0
        references[4::11, 0] = -1e-9  # a signed zero kept
        references[6::50, 2] = np.nan
        batch_q, batch_branch = solve.nearest(arm, solutions, references)
        found = 0
        for sols, ref, want_q, want_branch in zip(solutions, references, batch_q, batch_branch, strict=True):
            q, branch = solve.nearest(arm, sols, ref)
            assert int(branch) == int(want_branch), (family, sols, ref)
            np.testing.assert_array_equal(q, want_q)
            np.testing.assert_array_equal(np.signbit(q), np.signbit(want_q))
            found += int(branch) >= 0
        assert 0 < found < len(truth)


def test_one_pose_configuration_rules_are_the_batched_ones():
    """KUKA Status/Turn and ABB confdata for one pose (Python floats, codegen/robot/config.py) give what the
    batched numpy path gives: the same bits, joints (signed zeros too) and branch, with axes on the bits'
    and quadrants' boundaries, on the limits, branches missing (NaN) and configurations no branch has."""
    rng = np.random.default_rng(1623)
    for kin, limits in ((KR6_R700, KR6_LIMITS), (IRB2400, IRB2400_LIMITS)):
        arm = _arm(kin, limits)
        truth = rng.uniform(limits[:, 0], limits[:, 1], (400, 6))
        truth[::8, 4] = 0.0  # axis 5 on its bit's boundary
        truth[1::8, 4] = -0.0
        truth[2::8, 2] = kin.stretched_q3_deg  # the arm stretched: status bit 1's boundary
        truth[3::8, 0] = 90.0 * rng.integers(-1, 2, 50)  # a quadrant's boundary
        truth[4::8, 5] = limits[5, rng.integers(0, 2, 50)]  # on a limit
        solutions = kin.ik(kin.fk(truth))
        solutions[5::13, 2:4] = np.nan
        solutions[6::17, :, [0, 3, 5]] = -0.0  # signed zeros where a quadrant's turn is added
        for q in truth:
            assert kuka_status(kin, q) == int(kuka_status(kin, q[None])[0])
            assert kuka_turn(q) == int(kuka_turn(q[None])[0])
        picked = 0
        for i, q in enumerate(truth):
            status, turn = int(kuka_status(kin, q)), int(kuka_turn(q))
            conf = (*(int(v) for v in abb_quadrant(q[[0, 3, 5]])), int(abb_confdata(kin, q)[3]))
            if i % 5 == 0:  # a configuration no branch has here: none found, on both paths
                status, turn, conf = status ^ 7, turn ^ 63, (conf[0] + 2, *conf[1:])
            for select, value in ((by_status_turn, (status, turn)), (by_confdata, (conf,))):
                one_q, one_branch = select(arm, solutions[i], *value)
                many_q, many_branch = select(arm, solutions[i : i + 1], *value)
                assert int(one_branch) == int(many_branch[0]), (select.__name__, q, value)
                np.testing.assert_array_equal(one_q, many_q[0])
                np.testing.assert_array_equal(np.signbit(one_q), np.signbit(many_q[0]))
                picked += int(one_branch) >= 0
        assert 0 < picked < 2 * len(truth)
        # float32 values keep numpy's promotion (float32 arithmetic): the batched path takes them
        for i, q in enumerate(truth[:40]):
            conf = tuple(np.float32(v) for v in (*abb_quadrant(q[[0, 3, 5]]), abb_confdata(kin, q)[3]))
            one_q, one_branch = by_confdata(arm, solutions[i].astype(np.float32), conf)
            many_q, many_branch = by_confdata(arm, solutions[i : i + 1].astype(np.float32), conf)
            assert int(one_branch) == int(many_branch[0])
            np.testing.assert_array_equal(one_q, many_q[0])
