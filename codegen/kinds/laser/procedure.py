"""Source 003's automatic TCP method in float64, as a program would run it: two circles, the axis, the tip."""

# In the sensor frame S (codegen/sim/beams.py), with the flange's z pointing down S's -z (the tool
# pointing into the beams' plane) and the orientation held throughout:
# 1. Two horizontal circles of the flange, radius r, the guessed tip depth_1 and depth_2 below the beams'
#    plane. Sampled finely (the controllers catch a beam's change within an interpolation cycle), each
#    beam is interrupted twice per circle; the middle of an interruption is where the pin's axis crosses
#    the beam, and the reading there is where the beam meets the pin's surface.
# 2. Each circle's centre is the mean of its two crossings per beam (identity laser_circle_centre); the
#    tool axis comes from the two centres and the height step (laser_axis_from_two_centres: the pin's
#    radius cancels); the centres are then corrected for the radius, rho / sqrt(1 - u_x^2) along x and
#    likewise along y (laser_centre_corrected_for_the_pin).
# 3. The flange moves so that the axis meets the plane at the beams' crossing, rises along the axis, and
#    steps down along it (source 003: 0.1 mm) until a beam is interrupted (laser_step_keeps_the_axis);
#    the last step is then halved a few times (up if interrupted, else down), and the tip is on the
#    axis at the crossing, within the last half step of the plane.
# 4. The TCP in the flange frame is that point seen from the flange pose there.

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from codegen.sim.beams import Pin, Sensors

DOWN = np.diag([1.0, -1.0, -1.0])  # the flange's orientation in S: its z along S's -z


@dataclass(frozen=True)
class Procedure:
    """guess: tcp2flange the cell names (the tool as designed); radius: the pin's, as the cell says;
    circle_mm: the circles' radius; depths_mm: the guessed tip below the plane on each circle; step_mm:
    the tip search's step; samples: points per circle (how finely the beams are watched)."""

    guess: np.ndarray
    radius: float
    circle_mm: float = 20.0
    depths_mm: tuple[float, float] = (5.0, 15.0)
    step_mm: float = 0.1
    halvings: int = 8  # the last step halved so often (each a move and a look): 0.1 mm / 2^8 = 0.4 um
    clearance_mm: float = 10.0  # how far above the plane the search starts (the tool's length is a guess)
    samples: int = 7200
    correct_radius: bool = True  # False: the source as printed (the readings' centre taken as the axis)


@dataclass(frozen=True)
class Result:
    tcp: np.ndarray  # the TCP found, flange frame (mm)
    axis: np.ndarray  # the tool axis found, S (unit, up the pin)
    centres: tuple[np.ndarray, np.ndarray]  # the circles' centres in the beams' plane, corrected
    steps: int  # the tip search's steps
    moves: int  # every flange pose the procedure commands


def _flange(point: np.ndarray, guess: np.ndarray) -> np.ndarray:
    """flange2S with the guessed TCP at point (S), the flange pointing down."""
    out = np.eye(4)
    out[:3, :3] = DOWN
    out[:3, 3] = point - DOWN @ guess[:3, 3]
    return out


def _crossings(readings: list, angles: np.ndarray) -> list[tuple[float, float]]:
    """(angle, reading) at the middle of each run of interrupted samples (a circle: runs may wrap)."""
    on = [r is not None for r in readings]
    n = len(on)
    if all(on) or not any(on):
        return []
    start = next(i for i in range(n) if not on[i])  # begin on a free sample: every run is whole
    out, run = [], []
    for k in range(1, n + 1):
        i = (start + k) % n
        if on[i]:
            run.append(i)
        elif run:
            mid = run[len(run) // 2] if len(run) % 2 else run[len(run) // 2 - 1]
            out.append((float(angles[mid]), readings[mid]))
            run = []
    return out


def circle_centre(procedure: Procedure, pin: Pin, sensors: Sensors, to_true: np.ndarray, depth: float):
    """The circle at this depth: the mean crossing per beam, as positions along the beams (S x, y), and
    the number of poses commanded."""
    angles = np.linspace(0.0, 2.0 * math.pi, procedure.samples, endpoint=False)
    reads_x, reads_y = [], []
    for angle in angles:
        point = np.array([procedure.circle_mm * math.cos(angle), procedure.circle_mm * math.sin(angle), -depth])
        x, y = sensors.read(pin, to_true @ _flange(point, procedure.guess))
        reads_x.append(x)
        reads_y.append(y)
    cx, cy = _crossings(reads_x, angles), _crossings(reads_y, angles)
    if len(cx) != 2 or len(cy) != 2:
        raise ValueError(f"the circle at depth {depth:g} mm crossed beam X {len(cx)} and beam Y {len(cy)} times, not 2")
    centre = np.array([sum(r for _a, r in cx) / 2 - sensors.reach, sum(r for _a, r in cy) / 2 - sensors.reach])
    return centre, len(angles)


def run(procedure: Procedure, pin: Pin, sensors: Sensors, sensor_error: np.ndarray | None = None) -> Result:
    """The whole procedure; sensor_error: the true sensor frame in the one the cell names (the sensors
    read the pin where it truly is; the procedure computes in the named frame)."""
    to_true = np.linalg.inv(sensor_error) if sensor_error is not None else np.eye(4)
    c1, n1 = circle_centre(procedure, pin, sensors, to_true, procedure.depths_mm[0])
    c2, n2 = circle_centre(procedure, pin, sensors, to_true, procedure.depths_mm[1])
    # the circle's centre is where the guessed TCP's circle centre (the origin) puts the axis; going from
    # depth_1 to depth_2 the flange moved down by dz: the axis point moved by +dz (ux, uy)/uz
    dz = procedure.depths_mm[1] - procedure.depths_mm[0]
    slope = (c2 - c1) / dz
    axis = np.array([slope[0], slope[1], 1.0])
    axis /= np.linalg.norm(axis)
    if procedure.correct_radius:
        offset = procedure.radius * np.array([1 / math.sqrt(1 - axis[0] ** 2), 1 / math.sqrt(1 - axis[1] ** 2)])
        c1, c2 = c1 + offset, c2 + offset
    # put the axis through the crossing: the flange of circle 1's centre moved by -c1 in the plane, then
    # raised along the axis until the tip is clear, and stepped down along it
    flange = _flange(np.array([0.0, 0.0, -procedure.depths_mm[0]]), procedure.guess)
    flange[:3, 3] -= np.array([c1[0], c1[1], 0.0])
    flange[:3, 3] += axis * (procedure.depths_mm[0] + procedure.clearance_mm)
    steps = 0
    if any(sensors.blocked(pin, to_true @ flange)):
        raise ValueError("the tip is in a beam before the search starts: raise clearance_mm")
    while not any(sensors.blocked(pin, to_true @ flange)):
        flange[:3, 3] -= axis * procedure.step_mm
        steps += 1
        if steps > 10_000:
            raise ValueError("the tip search found no tip within 1 m")
    # the tip crossed the plane within the last step: halve it, keeping the flange where a beam sees the tip
    step, depth = procedure.step_mm, 0.0  # depth: how far the flange is below where the tip met the plane
    low, high = 0.0, step  # the tip's depth below the plane lies in [low, high)... as the flange now stands
    for _ in range(procedure.halvings):
        middle = (low + high) / 2
        probe = flange.copy()
        probe[:3, 3] += axis * middle
        steps += 1
        if any(sensors.blocked(pin, to_true @ probe)):
            low = middle
        else:
            high = middle
    depth = (low + high) / 2  # how far below the plane the beam first met the pin, the flange where it stands
    # a tilted end face meets a beam with its rim first: its centre (the tip) is then rho |u_x| / |(u_x, u_z)|
    # above the plane for beam X, likewise for Y (identity laser_tip_rim); the first beam is the larger
    if procedure.correct_radius:
        rim = procedure.radius * max(
            abs(axis[0]) / math.hypot(axis[0], axis[2]), abs(axis[1]) / math.hypot(axis[1], axis[2])
        )
    else:
        rim = 0.0
    tip = axis * ((rim - depth) / axis[2])  # on the axis through the crossing
    tcp = np.linalg.inv(flange) @ np.append(tip, 1.0)
    return Result(tcp[:3], axis, (c1, c2), steps, n1 + n2 + steps + 1)
