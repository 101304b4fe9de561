"""Configurations at an exact boundary: an axis at 0, 90 or 180 deg gets the boundary's own bits, whatever the sign of
the rounding; a configuration named for the boundary selects the boundary side only."""

from __future__ import annotations

import math

import numpy as np
import pytest
from support.cells import example

from codegen.kinds.pallet.plan import configurations
from codegen.kinds.pallet.reach import PICK_KEY
from codegen.kinds.pallet.section import pallets_of
from codegen.robot import solve
from codegen.robot.arms import Arm
from codegen.robot.config import (
    FORMS,
    ROUNDING_MARGIN_DEG,
    abb_confdata,
    abb_quadrant,
    by_confdata,
    by_status_turn,
    holding,
    kuka_status,
    kuka_turn,
    named_in_full,
    nearest_margin,
)
from codegen.robot.opw import OPW

KR6_R700 = OPW(25, -35, 0, 400, 315, 365, 80, (0, 90, 0, 0, 0, 0), (-1, 1, 1, -1, 1, -1))
KR6_LIMITS = np.array([[-170, 170], [-190, 45], [-120, 156], [-185, 185], [-120, 120], [-350, 350]], dtype=float)
IRB2400 = OPW(100, -135, 0, 615, 705, 755, 85, (0, 0, 90, 0, 0, 0), (1, 1, 1, 1, 1, 1))
IRB2400_LIMITS = np.array([[-180, 180], [-100, 110], [-60, 65], [-200, 200], [-120, 120], [-400, 400]], dtype=float)
NOISE = (0.0, -0.0, 1e-12, -1e-12, 3e-9, -3e-9)  # a float64 solution's rounding, at most 1e-6 deg


def _arm(kin, limits) -> Arm:
    return Arm("test", "test", "opw", kin, tuple(map(tuple, limits)), (0.0,) * 6)


@pytest.mark.parametrize("noise", NOISE)
def test_a_kuka_axis_at_zero_has_its_turn_bit_clear(noise):
    """Turn bit i is 1 only for axis i+1 < 0 (KSS 8 manual, Turn; Siemens TU: bit 0 for 0 <= theta): axis 1 and
    axis 4 at 0 (Q straight ahead, a vertical tool) have their bits 0 whatever the rounding's sign."""
    q = np.array([noise, -30.0, 20.0, noise, 45.0, 180.0 + noise])
    assert kuka_turn(q) == 2  # axis 2 alone is negative
    assert int(kuka_turn(q[None])[0]) == 2  # the batched path alike
    assert kuka_status(KR6_R700, q) == kuka_status(KR6_R700, np.array([0.0, -30.0, 20.0, 0.0, 45.0, 180.0]))


@pytest.mark.parametrize("noise", NOISE)
def test_an_abb_axis_on_a_quadrant_boundary_is_in_the_quadrant_it_opens(noise):
    """Quadrant 0 is 0 .. 90 deg, 2 is 180 .. 270 (RAPID data types, confdata): floor(angle / 90) of the boundary
    value itself, not of its rounding."""
    assert abb_quadrant(np.array([noise, 90.0 + noise, 180.0 + noise, -90.0 + noise])).tolist() == [0, 1, 2, -1]
    q = np.array([noise, 10.0, 10.0, noise, 30.0 + noise, 180.0 + noise])
    assert abb_confdata(IRB2400, q).tolist() == abb_confdata(IRB2400, np.array([0, 10, 10, 0, 30, 180.0])).tolist()
    assert abb_confdata(IRB2400, q).tolist()[:3] == [0, 0, 2]


def test_a_set_turn_bit_does_not_select_an_axis_at_its_boundary():
    """The Turn named for an axis at 0 (bit 0) selects it from either side of the rounding; a bit 1 there asks for
    the axis below 0 beyond the boundary, -360 deg here, which the KR 6's +-170 deg axis 1 refuses."""
    arm = _arm(KR6_R700, KR6_LIMITS)
    for noise in (1e-9, -1e-9):
        solutions = np.full((8, 6), np.nan)
        solutions[0] = [noise, -60.0, 100.0, 0.0, 50.0, 10.0]
        status = int(kuka_status(KR6_R700, solutions[0]))
        q, branch = by_status_turn(arm, solutions, status, 2)  # axis 2 negative, axis 1 at 0
        assert int(branch) == 0 and abs(q[0]) < 1e-6
        q, branch = by_status_turn(arm, solutions, status, 3)
        assert int(branch) == -1 and np.isnan(q).all()


def test_a_confdata_quadrant_selects_its_own_side_of_the_boundary():
    """cf6 = 2 (180 .. 270) takes axis 6 at 180 from either side of the rounding; cf6 = 1 (90 .. 180) does not."""
    arm = _arm(IRB2400, IRB2400_LIMITS)
    for noise in (1e-9, -1e-9):
        solutions = np.full((8, 6), np.nan)
        solutions[0] = [20.0, 10.0, 10.0, 30.0, 40.0, 180.0 + noise]
        cfx = int(abb_confdata(IRB2400, solutions[0])[3])
        q, branch = by_confdata(arm, solutions, (0, 0, 2, cfx))
        assert int(branch) == 0 and abs(q[5] - 180.0) < 1e-6
        q, branch = by_confdata(arm, solutions, (0, 0, 1, cfx))
        assert int(branch) == -1


def test_the_eur_cells_boundary_poses_name_the_boundarys_configuration():
    """Q of the EUR cell lies on the KR 210's axis 1 (y = 0): above Q, axis 1 is 0 and Turn bit 0 is clear (a
    set bit asks for axis 1 at -360 deg, beyond its +-185); box 1's entry has axis 4 at 0 (a vertical tool): its
    bit 3 is clear too. On the IRB 4600 axis 4 is 0 at Q and at every entry: cf4 = 0, not -1."""
    cell = example("eur_pallet")
    eur = pallets_of(cell)[0]
    status_turn = configurations(cell, eur, "kuka")
    _, turn = status_turn.values[PICK_KEY]
    assert turn & 1 == 0
    _, turn = status_turn.values[("interlock", 1)]
    assert turn >> 3 & 1 == 0
    confdata = configurations(cell, eur, "abb")
    assert all(value[1] == 0 for value in confdata.values.values()), confdata.values
    # and the programs name neither: the Turn and the quadrants there are decided by rounding (not whole)
    assert status_turn.whole is False and confdata.whole is False


def test_the_margin_is_far_above_the_rounding_and_far_below_a_real_turn():
    """1e-6 deg: float64 rounding is 1e-12; a pose taught 0.001 deg off the boundary keeps its own side."""
    assert solve.BOUNDARY_DEG == 1e-6
    assert kuka_turn(np.array([-1e-3, 0, 0, 0, 30.0, 0])) == 1
    assert FORMS["confdata"].of(_arm(IRB2400, IRB2400_LIMITS), np.array([0, 0, 0, -1e-3, 30.0, 0]))[1] == -1


@pytest.mark.parametrize("noise", NOISE)
def test_a_field_on_its_boundary_does_not_hold_whatever_the_rounding(noise):
    """A vertical tool puts KUKA's A4 at 0: the Turn depends on the rounding's sign there, the Status does not;
    ABB's cf1, cf4 and cf6 on a multiple of 90 deg depend on it too. The decision is the same for every sign
    and size of the rounding."""
    kuka = _arm(KR6_R700, KR6_LIMITS)
    q = np.array([20.0, -60.0, 100.0, noise, 50.0, 10.0])
    assert holding("status_turn", kuka, q).tolist() == [True, False]
    assert named_in_full("status_turn", kuka, q) is False
    abb = _arm(IRB2400, IRB2400_LIMITS)
    for axis, column in ((0, 0), (3, 1), (5, 2)):
        q = np.array([20.0, 10.0, 10.0, 30.0, 40.0, 100.0])
        q[axis] = 90.0 + noise
        held = holding("confdata", abb, q).tolist()
        assert held[column] is False and held.count(False) == 1, (axis, held)


def test_a_field_a_margin_away_from_its_boundary_holds():
    """0.02 deg from the boundary (twice the margin) the field is the controller's to compute as codegen does;
    the margin is a hundred times the 1e-4 deg a 32-bit controller's axis values differ by."""
    assert ROUNDING_MARGIN_DEG == 0.01
    kuka = _arm(KR6_R700, KR6_LIMITS)
    for a4 in (0.02, -0.02):
        assert named_in_full("status_turn", kuka, np.array([20.0, -60.0, 100.0, a4, 50.0, 10.0])) is True
    abb = _arm(IRB2400, IRB2400_LIMITS)
    assert named_in_full("confdata", abb, np.array([20.0, 10.0, 10.0, 30.0, 40.0, 90.02])) is True
    assert named_in_full("joints", abb, np.array([0.0, 0.0, 0.0, 0.0, 40.0, 0.0])) is True  # axis values: exact


def test_status_on_its_boundary_is_a_singular_pose_and_refused():
    """Status bit 2 is A5's sign: A5 at 0 is the wrist's singularity; a program cannot name even the Status."""
    kuka = _arm(KR6_R700, KR6_LIMITS)
    with pytest.raises(ValueError, match="singular"):
        named_in_full("status_turn", kuka, np.array([20.0, -60.0, 100.0, 10.0, 0.0, 10.0]))


def test_a_half_turn_either_way_is_a_tie_and_a_degree_off_is_not():
    """From axis 6 at 0 a target at 180 is as near at -180: the controller's nearest solution is not unique (margin
    0, axis 6); from axis 6 at 1 deg the +180 turn is 2 deg nearer than the -180 one."""
    kuka = _arm(KR6_R700, KR6_LIMITS)
    solutions = np.full((8, 6), np.nan)
    solutions[0] = [20.0, -60.0, 100.0, 0.0, 50.0, 180.0]
    margin, axis = nearest_margin(kuka, solutions, np.array([20.0, -60.0, 100.0, 0.0, 50.0, 0.0]))
    assert margin < 1e-9 and axis == 5
    margin, axis = nearest_margin(kuka, solutions, np.array([20.0, -60.0, 100.0, 0.0, 50.0, 1.0]))
    assert axis == 5 and margin == pytest.approx(math.hypot(181.0, 0.0) - 179.0, abs=1e-9)
    solutions[0, 5] = 90.0  # a quarter turn: the other turn is 270 away, the limits (+-350) hold both
    margin, _ = nearest_margin(kuka, solutions, np.array([20.0, -60.0, 100.0, 0.0, 50.0, 0.0]))
    assert margin == pytest.approx(270.0 - 90.0, abs=1e-9)
