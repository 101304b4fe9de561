"""The interpreters' fast pose arithmetic agrees with codegen.poses (matrices, float64)."""

import math

import numpy as np
from hypothesis import given
from hypothesis import strategies as st

from codegen import poses
from codegen.dialects import posemath

coord = st.floats(-2000, 2000)
angle = st.floats(-180, 180)
rv = st.tuples(st.floats(-2, 2), st.floats(-2, 2), st.floats(-2, 2)).filter(lambda v: math.hypot(*v) <= math.pi)


@given(st.tuples(coord, coord, coord), rv, st.tuples(coord, coord, coord), rv)
def test_ur_concat(ta, ra, tb, rb):
    a = (*(v / 1000 for v in ta), *ra)
    b = (*(v / 1000 for v in tb), *rb)
    expected = poses.matrix_from_ur(a) @ poses.matrix_from_ur(b)
    got = poses.matrix_from_ur(posemath.ur_concat(a, b))
    assert np.allclose(got, expected, atol=1e-9)
    assert np.allclose(posemath.matrix_from_ur(a), poses.matrix_from_ur(a), atol=1e-12)


@given(
    st.tuples(coord, coord, coord, angle, st.floats(-90, 90), angle),
    st.tuples(coord, coord, coord, angle, st.floats(-90, 90), angle),
)
def test_xyzabc_concat(a, b):
    expected = poses.matrix_from_xyzabc(a) @ poses.matrix_from_xyzabc(b)
    assert np.allclose(poses.matrix_from_xyzabc(posemath.xyzabc_concat(a, b)), expected, atol=1e-7)
    assert np.allclose(posemath.matrix_from_xyzabc(a), poses.matrix_from_xyzabc(a), atol=1e-12)


@given(st.tuples(angle, st.floats(-90, 90), angle))
def test_quaternion_round_trip(abc):
    r = posemath.rotmat_from_zyx_deg(*abc)
    q = posemath.quat_from_rotmat(r)
    assert np.allclose(q, poses.quat_from_rotmat(np.array(r).reshape(3, 3)), atol=1e-12)
    assert np.allclose(posemath.rotmat_from_quat(q), r, atol=1e-12)


quat = st.tuples(*[st.floats(-1, 1)] * 4).filter(lambda q: math.sqrt(sum(v * v for v in q)) > 0.1)


@given(quat, st.tuples(coord, coord, coord), quat)
def test_quaternion_rotation_and_product(q, v, q2):
    r = poses.rotmat_from_quat(q)  # normalises, as the controllers' pose functions do
    assert np.allclose(posemath.quat_rotate(q, v), r @ np.array(v), atol=1e-9)
    n = math.sqrt(sum(c * c for c in q))
    n2 = math.sqrt(sum(c * c for c in q2))
    product = posemath.quat_multiply([c / n for c in q], [c / n2 for c in q2])
    assert np.allclose(poses.rotmat_from_quat(product), r @ poses.rotmat_from_quat(q2), atol=1e-12)


@given(angle, st.floats(-90, 90), angle)
def test_orient_zyx_is_the_euler_rotation(a, b, c):
    q = posemath.quat_from_zyx_deg(a, b, c)
    assert math.isclose(math.sqrt(sum(v * v for v in q)), 1.0, abs_tol=1e-12)
    assert np.allclose(poses.rotmat_from_quat(q), poses.rotmat_from_zyx_deg(a, b, c), atol=1e-12)
