"""Pose conventions: round trips through 4x4 matrices, and their edge cases."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from codegen import poses

coord = st.floats(-2000, 2000, allow_nan=False)
angle = st.floats(-180, 180, allow_nan=False)


def assert_same_pose(m1, m2, pos_tol=1e-9, rot_tol=1e-9):
    assert np.max(np.abs(m1[:3, 3] - m2[:3, 3])) <= pos_tol
    assert np.max(np.abs(m1[:3, :3] - m2[:3, :3])) <= rot_tol


def assert_rotation(m):
    r = m[:3, :3]
    assert np.allclose(r.T @ r, np.eye(3), atol=1e-12)
    assert math.isclose(np.linalg.det(r), 1.0, abs_tol=1e-12)


@given(coord, coord, coord, angle, st.floats(-90, 90), angle)
def test_xyzabc_round_trip(x, y, z, a, b, c):
    m = poses.matrix_from_xyzabc((x, y, z, a, b, c))
    assert_rotation(m)
    back = poses.matrix_from_xyzabc(poses.xyzabc_from_matrix(m))
    assert_same_pose(m, back, rot_tol=1e-7)


@given(coord, coord, coord, angle, st.sampled_from([90.0, -90.0, 89.9999999, -89.9999999]), angle)
def test_xyzabc_gimbal_lock(x, y, z, a, b, c):
    m = poses.matrix_from_xyzabc((x, y, z, a, b, c))
    values = poses.xyzabc_from_matrix(m)
    assert_same_pose(m, poses.matrix_from_xyzabc(values), rot_tol=1e-6)


def test_xyzabc_known_values():
    # A = 90: x axis of the tool points along base y.
    m = poses.matrix_from_xyzabc((1, 2, 3, 90, 0, 0))
    assert np.allclose(m[:3, 0], [0, 1, 0])
    assert poses.xyzabc_from_matrix(m)[3] == 90.0
    assert poses.xyzabc_from_matrix(poses.matrix_from_xyzabc((0, 0, 0, 0, 0, -180)))[5] == 180.0


rotvec_angle = st.floats(0, math.pi, allow_nan=False)
unit = st.tuples(st.floats(-1, 1), st.floats(-1, 1), st.floats(-1, 1)).filter(
    lambda v: math.sqrt(sum(c * c for c in v)) > 0.1
)


@given(coord, coord, coord, unit, rotvec_angle)
def test_ur_round_trip(x, y, z, axis, ang):
    axis = np.array(axis) / np.linalg.norm(axis)
    rv = axis * ang
    m = poses.matrix_from_ur((x / 1000, y / 1000, z / 1000, *rv))
    assert_rotation(m)
    back = poses.ur_from_matrix(m)
    assert_same_pose(m, poses.matrix_from_ur(back), pos_tol=1e-9, rot_tol=1e-9)
    assert float(np.linalg.norm(back[3:])) <= math.pi + 1e-12


@given(unit, st.sampled_from([0.0, 1e-14, 1e-9, 1e-6, math.pi - 1e-9, math.pi - 1e-6, math.pi]))
def test_ur_rotvec_edges(axis, ang):
    axis = np.array(axis) / np.linalg.norm(axis)
    r = poses.rotmat_from_rotvec(axis * ang)
    rv = poses.rotvec_from_rotmat(r)
    assert np.allclose(poses.rotmat_from_rotvec(rv), r, atol=1e-9)
    if 1e-9 <= ang < math.pi - 1e-6:
        assert np.allclose(rv, axis * ang, atol=1e-8)


quat = st.tuples(*(st.floats(-1, 1) for _ in range(4))).filter(lambda q: math.sqrt(sum(c * c for c in q)) > 0.1)


@given(coord, coord, coord, quat)
def test_abb_round_trip_and_sign(x, y, z, q):
    q = np.array(q) / np.linalg.norm(q)
    m = poses.matrix_from_abb((x, y, z, *q))
    m_neg = poses.matrix_from_abb((x, y, z, *(-q)))
    assert_same_pose(m, m_neg)  # q and -q are the same rotation
    back = poses.abb_from_matrix(m)
    assert next(v for v in back[3:] if abs(v) > poses.QUAT_SIGN_TIE) > 0  # w > 0 but at a half turn
    assert_same_pose(m, poses.matrix_from_abb(back))
    assert np.allclose(np.abs(np.dot(back[3:], q)), 1.0, atol=1e-9)


@given(coord, coord, coord, angle, st.floats(-89, 89), angle)
def test_dtrans_is_xyzabc_reordered(x, y, z, a, b, c):
    m = poses.matrix_from_xyzabc((x, y, z, a, b, c))
    assert_same_pose(m, poses.matrix_from_dtrans((x, y, z, c, b, a)))
    assert_same_pose(m, poses.matrix_from_dtrans(poses.dtrans_from_matrix(m)), rot_tol=1e-7)


@settings(max_examples=50)
@given(coord, coord, coord, angle, st.floats(-89, 89), angle)
def test_formats_agree_through_matrices(x, y, z, a, b, c):
    m = poses.matrix_from_xyzabc((x, y, z, a, b, c))
    for _n, to_matrix, from_matrix, _desc in poses.POSE_FORMATS.values():
        assert_same_pose(m, to_matrix(from_matrix(m)), pos_tol=1e-9, rot_tol=1e-7)


def test_invert_and_concat():
    m = poses.matrix_from_xyzabc((10, 20, 30, 40, 50, 60))
    assert np.allclose(poses.concat(m, poses.invert(m)), np.eye(4), atol=1e-12)


@given(st.floats(-1e6, 1e6, allow_nan=False))
def test_wrap_deg_range(angle):
    out = poses.wrap_deg(angle)
    assert -180.0 < out <= 180.0
    assert math.isclose(math.remainder(out - angle, 360.0), 0.0, abs_tol=1e-9)
    assert out != 0.0 or math.copysign(1.0, out) == 1.0  # never -0.0


@pytest.mark.parametrize(
    "angle, expected",
    [
        (180.0, 180.0),
        (-180.0, 180.0),
        (540.0, 180.0),
        (-540.0, 180.0),
        (190.0, -170.0),
        (-359.0, 1.0),
        (0.0, 0.0),
        (-0.0, 0.0),  # the old reference.wrap_deg returned -0.0 here
        (-360.0, 0.0),  # and here
        (360.0, 0.0),
        (-720.0, 0.0),
    ],
)
def test_wrap_deg_values(angle, expected):
    out = poses.wrap_deg(angle)
    assert out == expected
    assert math.copysign(1.0, out) == math.copysign(1.0, expected)


def test_one_wrap():
    from codegen.dialects import posemath
    from codegen.kinds.station.modes import point

    assert posemath.wrap_deg is point.wrap_deg is poses.wrap_deg
