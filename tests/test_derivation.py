"""Derivation: every identity has its expected status, and the cache equals a fresh derivation."""

from __future__ import annotations

import json

import pytest

from codegen import derivation, derived
from codegen.kinds.pallet import derivation as pallet_derivation
from codegen.kinds.station import derivation as station_derivation

EXPECTED = {
    "zero_rotation_is_translation": "holds",
    "rigid": "holds",
    "mark_maps_to_mark": "holds",
    "yaw_addition": "holds",
    "source_eq13": "refuted",
    "source_eq13_rigid": "refuted",
    "source_listing_as_named": "refuted",
    "source_listing_names_swapped": "holds",
    "source_listing_orientation_sign": "refuted",
    "frame_update": "holds",
    "source_frame_update": "refuted",
    "source_frame_update_contraction": "holds",
    "pallet_frame_orthonormal": "holds",
    "source_pallet_frame": "refuted",
    "box_orientation_one_turn": "holds",
    "box_pose_on_a_level_pallet": "holds",
    "box_offset_in_the_pallet_frame": "holds",
    "box_offset_along_the_tool": "refuted",
    "laser_circle_centre": "holds",
    "laser_surface_at_crossing": "holds",
    "source_laser_centre_from_readings": "refuted",
    "laser_centre_corrected_for_the_pin": "holds",
    "laser_axis_from_two_centres": "holds",
    "laser_step_keeps_the_axis": "holds",
    "laser_tip_rim": "holds",
    "laser_edges_centre": "holds",
    "laser_tip_on_beam": "holds",
    "source_laser_tip_uncorrected": "refuted",
    "laser_frame_chord": "holds",
    "laser_frame_yaw": "holds",
    "laser_frame_crossing": "holds",
    "laser_frame_parallel_beams": "holds",
    "laser_frame_no_step": "holds",
    "laser_frame_slope": "holds",
    "laser_frame_one_search_point": "holds",
}


def test_source_004_pallet_frame_error_for_py_five_degrees_off_square():
    """The test's own number: with PY turned 5 deg from square, x . m = cos(85 deg) = sin(5 deg)."""
    import math

    (pallet,) = [i for i in pallet_derivation.pallet_identities(derivation._check) if i.name == "source_pallet_frame"]
    residual = float(pallet.detail.rsplit("residual ", 1)[1])
    assert residual == pytest.approx(math.sin(math.radians(5.0)), rel=1e-5)


@pytest.fixture(scope="module")
def fresh():
    return station_derivation.derive()


def test_identities_have_expected_status(fresh):
    result = {i.name: i.status for i in derivation.identities({"station": fresh})}
    assert result == EXPECTED


def test_solution_is_the_rigid_formula(fresh):
    # Independent of the solver: Pn = tn + R(phi)(P - t), typed here as the test's own statement.
    import sympy as sp

    s = station_derivation
    expected = s.tn + s.rot2(s.phi) * (s.P - s.t)
    assert all(sp.simplify(e) == 0 for e in fresh.Pn - expected)


def test_refuted_identity_reports_a_counterexample(fresh):
    eq13 = next(i for i in derivation.identities({"station": fresh}) if i.name == "source_eq13")
    assert eq13.detail.startswith("at ") and "residual" in eq13.detail


def test_cache_equals_fresh_derivation():
    fresh_cache = json.loads(json.dumps(derivation.build_cache(), sort_keys=True))
    assert derived.load() == fresh_cache, "codegen/derived.json is stale: python -m codegen.derivation --write"


def test_contraction_factor_is_derived():
    import sympy as sp

    factor = station_derivation.source_frame_contraction()
    assert sp.simplify(factor - 2 * sp.Abs(sp.sin(station_derivation.alpha))) == 0
    # diverges past 30 degrees: 2 sin(30 deg) = 1
    assert float(factor.subs(station_derivation.alpha, sp.pi / 6)) == 1.0


def test_describe_shows_both_updates():
    text = derivation.describe()
    assert "R(+alpha)" in text and "R(-alpha)" in text and "2*Abs(sin(alpha))" in text
