"""Reference: guard order, wrap, and agreement with the derived closed form."""

from __future__ import annotations

import math
import random

import numpy as np
import pytest
from support.closed_forms import evaluate

from codegen.guard import INVALID_READING, ROTATION_OVER_LIMIT, SHIFT_OVER_LIMIT, UNKNOWN_STATION
from codegen.kinds.station.point.reference import Reading, expected_trace
from codegen.kinds.station.section import section_of, stations_of
from codegen.poses import wrap_deg


def test_closed_form_agrees_with_matrices(demo_cell):
    rng = random.Random(2026)
    worst = 0.0
    for _ in range(2000):
        station = rng.choice(stations_of(demo_cell))
        tx, ty, t_theta = station.spec.mark
        reading = Reading(
            station.id, tx + rng.uniform(-7, 7), ty + rng.uniform(-7, 7), t_theta + rng.uniform(-9.9, 9.9)
        )
        trace = expected_trace(demo_cell, reading)
        assert trace.status == "ok"
        phi = math.radians(trace.detail.phi_deg)
        frame = evaluate("frame", {"tx": tx, "ty": ty, "tnx": reading.x, "tny": reading.y, "phi": phi})
        d = trace.detail.correction
        assert abs(frame["frame_cos"] - d[0, 0]) < 1e-12
        assert abs(frame["frame_sin"] - d[1, 0]) < 1e-12
        worst = max(worst, abs(frame["frame_x"] - d[0, 3]), abs(frame["frame_y"] - d[1, 3]))
        for pose, move in zip(station.path, trace.moves, strict=True):
            m = pose.matrix()
            if pose.name in station.spec.fixed:  # on the AGV with the robot: as taught
                assert np.array_equal(move.tcp2base, m)
                continue
            point = evaluate(
                "point",
                {"tx": tx, "ty": ty, "tnx": reading.x, "tny": reading.y, "phi": phi, "Px": m[0, 3], "Py": m[1, 3]},
            )
            worst = max(worst, abs(point["point_x"] - move.tcp2base[0, 3]), abs(point["point_y"] - move.tcp2base[1, 3]))
    assert worst <= 1e-9


def test_zero_shift_gives_taught_poses(demo_cell):
    station = stations_of(demo_cell)[5]
    trace = expected_trace(demo_cell, Reading(station.id, *station.spec.mark))
    for pose, move in zip(station.path, trace.moves, strict=True):
        assert np.allclose(move.tcp2base, pose.matrix(), atol=1e-12)
    assert [m.kind for m in trace.moves] == ["joint", "linear", "linear"]  # approach, work pose, retreat


def test_pure_translation(demo_cell):
    station = stations_of(demo_cell)[0]
    tx, ty, t_theta = station.spec.mark
    trace = expected_trace(demo_cell, Reading(station.id, tx + 3, ty - 4, t_theta))
    for pose, move in zip(station.path, trace.moves, strict=True):
        shift = [0, 0, 0] if pose.name in station.spec.fixed else [3, -4, 0]
        assert np.allclose(move.tcp2base[:3, 3] - pose.matrix()[:3, 3], shift, atol=1e-12)


def test_fixed_poses_stay_as_taught_and_the_others_turn(demo_cell):
    """A reading turned 5 deg moves the machine's poses and leaves the tray's (on the AGV with the robot) alone."""
    station = stations_of(demo_cell)[0]
    tx, ty, t_theta = station.spec.mark
    trace = expected_trace(demo_cell, Reading(station.id, tx, ty, t_theta + 5.0))
    moved = {
        p.name: float(np.linalg.norm(m.tcp2base[:3, 3] - p.matrix()[:3, 3]))
        for p, m in zip(station.path, trace.moves, strict=True)
    }
    assert {name for name, d in moved.items() if d == 0.0} == set(station.spec.fixed) and station.spec.fixed
    assert all(d > 1.0 for name, d in moved.items() if name not in station.spec.fixed)


def test_guard_order_and_reasons(demo_cell):
    s = stations_of(demo_cell)[0]
    tx, ty, t_theta = s.spec.mark
    assert expected_trace(demo_cell, Reading(99, math.nan, 0, 0)).reason == UNKNOWN_STATION
    assert expected_trace(demo_cell, Reading(s.id, math.nan, ty, t_theta)).reason == INVALID_READING
    assert expected_trace(demo_cell, Reading(s.id, tx, math.inf, t_theta)).reason == INVALID_READING
    assert expected_trace(demo_cell, Reading(s.id, tx, ty, 400.0)).reason == INVALID_READING
    assert expected_trace(demo_cell, Reading(s.id, tx + 20, ty, 50.0)).reason == SHIFT_OVER_LIMIT
    assert expected_trace(demo_cell, Reading(s.id, tx + 6, ty + 8, t_theta)).status == "ok"  # exactly 10
    assert expected_trace(demo_cell, Reading(s.id, tx + 6, ty + 8.001, t_theta)).reason == SHIFT_OVER_LIMIT
    assert expected_trace(demo_cell, Reading(s.id, tx, ty, t_theta + 10.0)).status == "ok"
    assert expected_trace(demo_cell, Reading(s.id, tx, ty, t_theta + 10.01)).reason == ROTATION_OVER_LIMIT


def test_rotation_wraps_at_180(demo_cell):
    s = section_of(demo_cell).station_by_id(6)  # mark theta 178.6 deg
    trace = expected_trace(demo_cell, Reading(6, s.spec.mark[0], s.spec.mark[1], -178.4))
    assert trace.status == "ok"
    assert trace.detail.rotation_deg == pytest.approx(3.0)
    assert trace.detail.phi_deg == pytest.approx(-3.0)  # angle_sign -1


def test_wrap_deg():
    assert wrap_deg(180.0) == 180.0
    assert wrap_deg(-180.0) == 180.0
    assert wrap_deg(190.0) == pytest.approx(-170.0)
    assert wrap_deg(-359.0) == pytest.approx(1.0)


def test_deviation_line(demo_cell):
    s = stations_of(demo_cell)[0]
    tx, ty, t_theta = s.spec.mark
    trace = expected_trace(demo_cell, Reading(s.id, tx + 1, ty + 2, t_theta + 3))
    sid, dx1, dy1, dx2, dy2, dtheta = trace.logged
    work_before, work_after = s.poses[-1].matrix(), trace.moves[-1].tcp2base
    assert (sid, dx2, dy2) == (1.0, pytest.approx(1.0), pytest.approx(2.0))
    assert dtheta == pytest.approx(-3.0)
    assert dx1 == pytest.approx(work_after[0, 3] - work_before[0, 3])
    assert dy1 == pytest.approx(work_after[1, 3] - work_before[1, 3])
