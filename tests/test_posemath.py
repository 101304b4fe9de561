"""The interpreters' fast pose arithmetic agrees with codegen.poses (matrices, float64)."""

import math

import numpy as np
import pytest
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


# --- every numpy function against its scalar twin (same name in both modules) ------------------

quat_any = st.tuples(*[st.floats(-1, 1)] * 4).filter(lambda q: math.sqrt(sum(v * v for v in q)) > 1e-3)
b_angle = st.one_of(st.floats(-90, 90), st.sampled_from([90.0, -90.0, 89.9999999, -89.9999999]))
rotvec_angle = st.one_of(
    st.floats(0, math.pi), st.sampled_from([0.0, 1e-14, 1e-9, math.pi - 1e-9, math.pi - 1e-6, math.pi])
)
axis = st.tuples(*[st.floats(-1, 1)] * 3).filter(lambda v: math.hypot(*v) > 0.1)
xyz = st.tuples(coord, coord, coord)


def _rotvec(ax, ang) -> tuple[float, float, float]:
    n = math.hypot(*ax)
    return (ax[0] / n * ang, ax[1] / n * ang, ax[2] / n * ang)


def _as_rotmat(r9) -> np.ndarray:
    return np.array(r9).reshape(3, 3)


def test_the_shared_names():
    """posemath's conversions carry codegen.poses's names; the matrix -> pose ones are the numpy functions."""
    conversions = {n for n in dir(posemath) if "_from_" in n and not n.startswith("_")}
    assert conversions - set(dir(poses)) == {"quat_from_zyx_deg", "matrix_from_ur_cached"}
    assert posemath.ur_from_matrix is poses.ur_from_matrix
    assert posemath.xyzabc_from_matrix is poses.xyzabc_from_matrix
    assert posemath.wrap_deg is poses.wrap_deg


@given(quat_any)
def test_rotmat_from_quat_twin(q):
    r = posemath.rotmat_from_quat(q)
    assert np.array_equal(_as_rotmat(r), poses.rotmat_from_quat(q))  # same arithmetic, same floats
    assert posemath.rotmat_from_quat(tuple(-v for v in q)) == r  # q and -q: one rotation
    assert np.array_equal(poses.rotmat_from_quat(np.negative(q)), poses.rotmat_from_quat(q))


@given(quat_any)
def test_quat_from_rotmat_twin(q):
    rot = poses.rotmat_from_quat(q)
    got = posemath.quat_from_rotmat(tuple(rot.ravel()))
    want = poses.quat_from_rotmat(rot)
    assert np.allclose(got, want, rtol=0, atol=1e-14)
    assert got[0] >= -poses.QUAT_SIGN_TIE and want[0] >= -poses.QUAT_SIGN_TIE
    n = math.sqrt(sum(v * v for v in q))
    assert np.allclose(np.abs(np.dot(got, q)) / n, 1.0, atol=1e-12)  # q or -q, the sign of shown_quat
    assert posemath.quat_from_rotmat(posemath.rotmat_from_quat(tuple(-v for v in q))) == got


@pytest.mark.parametrize(
    "q", [(0.0, 1.0, 0.0, 0.0), (0.0, 0.0, -1.0, 0.0), (0.0, 0.6, 0.0, -0.8), (0.0, 0.5, 0.5, 0.5**0.5)]
)
def test_quat_from_rotmat_at_pi(q):
    """Rotations of pi (w = 0): q and -q are the same rotation; both modules pick the same sign."""
    for sign in (1.0, -1.0):
        qs = tuple(sign * v for v in q)
        rot = poses.rotmat_from_quat(qs)
        got, want = posemath.quat_from_rotmat(tuple(rot.ravel())), poses.quat_from_rotmat(rot)
        assert np.allclose(got, want, rtol=0, atol=1e-14)
        assert np.allclose(np.abs(np.dot(got, q)), 1.0, atol=1e-12)
        assert np.allclose(_as_rotmat(posemath.rotmat_from_quat(got)), rot, atol=1e-14)


@given(axis, rotvec_angle)
def test_rotmat_from_rotvec_twin(ax, ang):
    rv = _rotvec(ax, ang)
    assert np.allclose(_as_rotmat(posemath.rotmat_from_rotvec(rv)), poses.rotmat_from_rotvec(rv), rtol=0, atol=1e-14)


@given(axis, rotvec_angle)
def test_rotvec_from_rotmat_twin(ax, ang):
    rv = _rotvec(ax, ang)
    rot = poses.rotmat_from_rotvec(rv)
    got, want = posemath.rotvec_from_rotmat(tuple(rot.ravel())), poses.rotvec_from_rotmat(rot)
    assert np.allclose(got, want, rtol=0, atol=1e-14)
    assert math.hypot(*got) <= math.pi + 1e-12
    assert np.allclose(_as_rotmat(posemath.rotmat_from_rotvec(got)), rot, atol=1e-9)
    if ang < math.pi - 1e-6:
        assert np.allclose(got, rv, atol=1e-8)
    else:  # near pi: rv or -rv (the same rotation at pi)
        assert np.allclose(got, rv, atol=1e-5) or np.allclose(got, np.negative(rv), atol=1e-5)


@pytest.mark.parametrize(
    "rv", [(math.pi, 0.0, 0.0), (0.0, -math.pi, 0.0), (0.0, 0.0, math.pi), _rotvec((1, -2, 2), math.pi)]
)
def test_rotvec_at_pi(rv):
    rot = poses.rotmat_from_rotvec(rv)
    assert np.allclose(_as_rotmat(posemath.rotmat_from_rotvec(rv)), rot, rtol=0, atol=1e-14)
    got, want = posemath.rotvec_from_rotmat(tuple(rot.ravel())), poses.rotvec_from_rotmat(rot)
    assert np.allclose(got, want, rtol=0, atol=1e-14)
    assert math.isclose(math.hypot(*got), math.pi, abs_tol=1e-12)
    assert np.allclose(got, rv, atol=1e-12) or np.allclose(got, np.negative(rv), atol=1e-12)
    assert np.allclose(poses.rotmat_from_rotvec(got), rot, atol=1e-12)


@given(angle, b_angle, angle)
def test_rotmat_from_zyx_deg_twin(a, b, c):
    r = posemath.rotmat_from_zyx_deg(a, b, c)
    assert np.allclose(_as_rotmat(r), poses.rotmat_from_zyx_deg(a, b, c), rtol=0, atol=1e-14)


@given(angle, b_angle, angle)
def test_zyx_deg_from_rotmat_twin(a, b, c):
    rot = poses.rotmat_from_zyx_deg(a, b, c)
    got = posemath.zyx_deg_from_rotmat(tuple(rot.ravel()))
    assert got == poses.zyx_deg_from_rotmat(rot)  # same arithmetic, same floats
    for v in (got[0], got[2]):
        assert -180.0 < v <= 180.0
        assert v != 0.0 or math.copysign(1.0, v) == 1.0  # never -0.0
    assert np.allclose(_as_rotmat(posemath.rotmat_from_zyx_deg(*got)), rot, atol=1e-9)


@pytest.mark.parametrize("b", [90.0, -90.0])
@pytest.mark.parametrize("a, c", [(0.0, 0.0), (30.0, -45.0), (-170.0, 170.0), (180.0, 180.0)])
def test_zyx_gimbal_lock(a, b, c):
    """At b = +-90 only a - c (b = 90) or a + c (b = -90) is defined: both modules set c = 0."""
    rot = poses.rotmat_from_zyx_deg(a, b, c)
    got = posemath.zyx_deg_from_rotmat(tuple(rot.ravel()))
    assert got == poses.zyx_deg_from_rotmat(rot)
    assert got[2] == 0.0 and math.copysign(1.0, got[2]) == 1.0
    assert math.isclose(got[1], b, abs_tol=1e-9)
    assert np.allclose(poses.rotmat_from_zyx_deg(*got), rot, atol=1e-12)


@given(xyz, quat_any)
def test_matrix_from_rotation_translation_twin(t, q):
    r = posemath.rotmat_from_quat(q)
    assert np.array_equal(
        posemath.matrix_from_rotation_translation(r, t), poses.matrix_from_rotation_translation(_as_rotmat(r), t)
    )


@given(xyz, axis, rotvec_angle)
def test_matrix_from_ur_twin(t, ax, ang):
    pose = (*(v / 1000 for v in t), *_rotvec(ax, ang))
    want = poses.matrix_from_ur(pose)
    assert np.allclose(posemath.matrix_from_ur(pose), want, rtol=0, atol=1e-12)
    assert np.array_equal(posemath.matrix_from_ur_cached(pose), want)  # the numpy function, memoised
    assert posemath.ur_from_matrix(want) == poses.ur_from_matrix(want)


@given(xyz, angle, b_angle, angle)
def test_matrix_from_xyzabc_twin(t, a, b, c):
    pose = (*t, a, b, c)
    want = poses.matrix_from_xyzabc(pose)
    assert np.allclose(posemath.matrix_from_xyzabc(pose), want, rtol=0, atol=1e-12)
    assert posemath.xyzabc_from_matrix(want) == poses.xyzabc_from_matrix(want)


@given(xyz, quat_any)
def test_matrix_from_abb_twin(t, q):
    pose = (*t, *q)
    assert np.array_equal(posemath.matrix_from_abb(pose), poses.matrix_from_abb(pose))
    assert np.array_equal(posemath.matrix_from_abb((*t, *(-v for v in q))), poses.matrix_from_abb(pose))


@given(st.tuples(coord, coord, coord, angle, b_angle, angle), st.tuples(coord, coord, coord, angle, b_angle, angle))
def test_xyzabc_concat_through_gimbal_lock(a, b):
    expected = poses.concat(poses.matrix_from_xyzabc(b), poses.matrix_from_xyzabc(a))
    assert np.allclose(poses.matrix_from_xyzabc(posemath.xyzabc_concat(a, b)), expected, atol=1e-6)


@given(st.tuples(coord, coord, coord), axis, rotvec_angle, st.tuples(coord, coord, coord), axis, rotvec_angle)
def test_ur_concat_with_rotations_of_pi(ta, axa, anga, tb, axb, angb):
    a = (*(v / 1000 for v in ta), *_rotvec(axa, anga))
    b = (*(v / 1000 for v in tb), *_rotvec(axb, angb))
    expected = poses.concat(poses.matrix_from_ur(b), poses.matrix_from_ur(a))
    assert np.allclose(poses.matrix_from_ur(posemath.ur_concat(a, b)), expected, atol=1e-9)
