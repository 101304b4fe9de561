"""Source 003's automatic TCP method, its float64 reference against two simulated laser sensors."""

from __future__ import annotations

import numpy as np
import pytest

from codegen.kinds.laser.procedure import Procedure, run
from codegen.poses import rotmat_from_zyx_deg
from codegen.sim.beams import Pin, Sensors, entry_along

GUESS = np.eye(4)
GUESS[2, 3] = 200.0  # the tool as the cell names it: 200 mm along the flange's z


def _tool(length: float, bend_deg: float, lateral, yaw_deg: float) -> np.ndarray:
    """A pin bent off the flange's axis: turned by bend_deg about an axis at yaw_deg, its tip offset."""
    out = np.eye(4)
    out[:3, :3] = rotmat_from_zyx_deg(yaw_deg, bend_deg, 0.0)
    out[:3, 3] = (lateral[0], lateral[1], length)
    return out


def test_a_beam_enters_a_pin_where_the_geometry_says():
    """A vertical pin of radius 2 at x = 20 on beam X: the beam meets it at 18 mm, 118 mm from the sensor
    100 mm away; a pin tilted 30 deg about y meets it 2 / cos(30 deg) before its axis; a pin 5 mm above
    the beams' plane is not seen."""
    up = np.array([0.0, 0.0, 1.0])
    origin, along = np.array([-100.0, 0.0, 0.0]), np.array([1.0, 0.0, 0.0])
    assert entry_along(np.array([20.0, 0.0, -5.0]), up, 2.0, 60.0, origin, along) == pytest.approx(118.0)
    tilted = np.array([np.sin(np.radians(30)), 0.0, np.cos(np.radians(30))])
    tip = np.array([20.0, 0.0, 0.0]) - 5.0 * tilted  # the axis meets the plane at x = 20
    assert entry_along(tip, tilted, 2.0, 60.0, origin, along) == pytest.approx(120.0 - 2.0 / np.cos(np.radians(30)))
    assert entry_along(np.array([20.0, 0.0, 5.0]), up, 2.0, 60.0, origin, along) is None


@pytest.mark.parametrize("seed", range(4))
def test_the_reference_recovers_a_bent_tool_within_a_tenth(seed):
    """Random pins (radius 1-3 mm, up to 3 deg off the flange's axis, the tip up to 2 mm aside and 3 mm
    along it), sensors with 0.01 mm of noise and a 1 um resolution: the TCP within 0.1 mm (issue 13)."""
    rng = np.random.default_rng(seed)
    true = _tool(rng.uniform(197, 203), rng.uniform(-3, 3), rng.uniform(-2, 2, 2), rng.uniform(-180, 180))
    radius = rng.uniform(1, 3)
    result = run(Procedure(GUESS, radius, samples=2400), Pin(true, radius), Sensors(noise=0.01, resolution=0.001))
    assert np.linalg.norm(result.tcp - true[:3, 3]) < 0.1
    # the axis from two centres 10 mm apart, each the mean of two readings of 0.01 mm noise: a slope of
    # sqrt(2) 0.007 / 10 rad, 0.06 deg one sigma; within three
    true_axis = -true[:3, 2] * np.array([1, -1, -1])  # up the pin, in the sensor frame (the flange points down)
    assert np.degrees(np.arccos(min(1.0, np.dot(result.axis, true_axis)))) < 0.2


def test_the_source_as_printed_misses_by_the_pins_radius():
    """Without the radius correction (the readings' centre taken as the axis, the tip's centre taken where
    a beam first sees the end face) the same pin is found more than a millimetre off."""
    true = _tool(201.0, 2.0, (0.5, -0.8), 40.0)
    procedure = Procedure(GUESS, 2.0, samples=2400, correct_radius=False)
    result = run(procedure, Pin(true, 2.0), Sensors())
    assert np.linalg.norm(result.tcp - true[:3, 3]) > 1.0


def test_a_sensor_frame_error_is_not_seen_by_the_method():
    """The sensors 0.1 mm from where the cell says: the TCP is off by about that much (the method measures
    the tool against the sensors, not the sensors against the robot)."""
    true = _tool(200.5, 1.0, (0.3, 0.2), 10.0)
    error = np.eye(4)
    error[:3, 3] = (0.1, 0.0, 0.0)
    result = run(Procedure(GUESS, 2.0, samples=2400), Pin(true, 2.0), Sensors(), sensor_error=error)
    assert 0.05 < np.linalg.norm(result.tcp - true[:3, 3]) < 0.15


def test_a_tilted_pins_end_is_seen_at_its_rim_and_corrected():
    """A 3 mm pin bent 3 deg: a beam first meets its end face 3 sin(3 deg) = 0.16 mm below the tip's
    centre (identity laser_tip_rim); corrected, the TCP comes out within 0.02 mm (no noise)."""
    true = _tool(200.0, 3.0, (0.0, 0.0), 0.0)
    result = run(Procedure(GUESS, 3.0, samples=2400), Pin(true, 3.0), Sensors())
    assert np.linalg.norm(result.tcp - true[:3, 3]) < 0.02
