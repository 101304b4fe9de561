"""The setup run with a reference pin that measures the sensor frame: its poses, its program's context, S found."""

from __future__ import annotations

import math

import numpy as np

from codegen.emit import Emitter, owned
from codegen.kinds.laser.kind import KIND
from codegen.kinds.laser.section import laser_of
from codegen.model.cell import TaughtPose
from codegen.poses import zyx_deg_from_rotmat

# The run (frame_derivation.py proves its geometry, frame_solve.py solves it in float64): the reference pin, its axis
# along the named S's z, its tip depths_mm[0] below the beams' plane, runs three circles of radius circle_mm about
# (0, 0), (delta, 0) and (0, delta), delta = circle_mm / 2 (each still crosses both beams: delta + the pin's radius
# + offset_max_mm < circle_mm, section.py checks it); then four tip searches straight down, at circle_mm either
# side of the crossing along each beam (where the circles put it). The program solves the beams on the controller
# and shows the sensor frame found in the base frame: the cell engineer puts it into [laser] sensor_frame.
FRAME_FOUND = "laser: sensor frame found, base mm deg: "
FRAME_FOUND_XYZ = "laser: sensor frame found, base x y z mm: "  # messages of three numbers each
FRAME_FOUND_ABC = "laser: sensor frame found, base a b c deg: "
FRAME_START_AWAY = "laser: start the setup run with the arm at home"
FRAME_NO_YAW = "laser: setup circles do not agree on the beams' yaw, check the pin"
FRAME_CIRCLE = "laser: setup circle did not cross both beams twice, circle "
FRAME_NO_CONTACT = "laser: setup search found no beam within clearance_mm, search "
FRAME_NAMES = {"frame": "LSR_FRAME", "beams": "LSR_BEAMS", "means": "LSR_MEANS", "contacts": "LSR_CONTACTS"}


def sets_up(cell, target) -> bool:
    """Whether the cell names a reference pin and the target writes the setup program."""
    laser = laser_of(cell)
    return laser is not None and laser.reference_tcp_mm is not None and bool(KIND.facts(target).get("frame_files"))


def step_mm(laser) -> float:
    """delta: how far the second and third circles' centres lie from the first's."""
    return laser.circle_mm / 2.0


def span_mm(laser) -> float:
    """How far each search point lies from the crossing, along x (beam X) or y (beam Y)."""
    return laser.circle_mm


def circle_points(laser, centre: tuple[float, float]) -> dict[str, tuple[float, float, float]]:
    """A setup circle's poses' positions in S (mm): above, start, via1, mid, via2 (counterclockwise from 45 deg)."""
    h, (cx, cy), z = laser.circle_mm / math.sqrt(2.0), centre, -laser.depths_mm[0]
    return {
        "above": (cx + h, cy + h, laser.clearance_mm),
        "start": (cx + h, cy + h, z),
        "via1": (cx - h, cy + h, z),
        "mid": (cx - h, cy - h, z),
        "via2": (cx + h, cy - h, z),
    }


def centres(laser) -> list[tuple[float, float]]:
    delta = step_mm(laser)
    return [(0.0, 0.0), (delta, 0.0), (0.0, delta)]


def reference_tool(laser) -> np.ndarray:
    """The reference pin's tcp2flange (4x4, mm): its TCP, its axis along the flange's z."""
    out = np.eye(4)
    out[:3, 3] = laser.reference_tcp_mm
    return out


def frame_found(named2base: np.ndarray, beams: dict) -> np.ndarray:
    """S as the beams lie (4x4, base): origin at their crossing d, x along beam X, z square to both beams
    (frame_solve.solve_frame's d, yaws and slopes, in the named S)."""
    t_x, t_y, s_x, s_y = beams["t_x"], beams["t_y"], beams["s_x"], beams["s_y"]
    b = np.array([1.0, t_x, s_x * math.sqrt(1.0 + t_x * t_x)])
    a = np.array([t_y, 1.0, s_y * math.sqrt(1.0 + t_y * t_y)])
    x = b / np.linalg.norm(b)
    z = np.cross(b, a)
    z /= np.linalg.norm(z)
    found = np.eye(4)
    found[:3, :3] = np.column_stack([x, np.cross(z, x), z])
    found[:3, 3] = beams["d"]
    return named2base @ found


def xyzabc(matrix: np.ndarray) -> tuple[float, ...]:
    return tuple(float(v) for v in (*matrix[:3, 3], *zyx_deg_from_rotmat(matrix[:3, :3])))


def frame_context(cell, target, emitter: Emitter) -> dict:
    """The setup program's template variables (mm, S; the reference pin's TCP in the flange frame)."""
    laser = laser_of(cell)
    number = emitter.number
    named = laser.sensor_frame.matrix()
    down = np.diag([1.0, -1.0, -1.0])
    return {
        "ident": emitter.identifier("frame_", cell.name, "the laser setup program"),
        "reference": [number(v, 4) for v in laser.reference_tcp_mm],
        "reference_radius": number(laser.reference_radius_mm, 4),
        "sensor": emitter.pose(laser.sensor_frame),
        "down": emitter.pose(TaughtPose("down", (0.0, 0.0, 0.0, *zyx_deg_from_rotmat(down)), "xyzabc")),
        "named_r": [number(v, 9) for v in named[:3, :3].reshape(-1)],
        "named_p": [number(v, 4) for v in named[:3, 3]],
        "circles": [
            {k: [number(v, 4) for v in xyz] for k, xyz in circle_points(laser, c).items()} for c in centres(laser)
        ],
        "radius": number(laser.circle_mm, 4),
        "depth": number(laser.depths_mm[0], 4),
        "delta": number(step_mm(laser), 4),
        "span": number(span_mm(laser), 4),
        "clearance": number(laser.clearance_mm, 4),
        "safe": [number(v, 4) for v in (*circle_points(laser, (0.0, 0.0))["start"][:2], laser.safe_height_mm)],
        "found": emitter.string(FRAME_FOUND),
        "found_xyz": emitter.string(FRAME_FOUND_XYZ),
        "found_abc": emitter.string(FRAME_FOUND_ABC),
        "no_yaw": emitter.string(FRAME_NO_YAW),
        "start_away": emitter.string(FRAME_START_AWAY),
        "circle_edges": emitter.string(FRAME_CIRCLE),
        "no_contact": emitter.string(FRAME_NO_CONTACT),
        "names": owned(dict(FRAME_NAMES)),
        # the entry routine where the program is a module of the production task (whose main is its own)
        "entry": emitter.identifier("frame_", f"{cell.name}_run", "the laser setup program's entry routine")
        if KIND.facts(target).get("entry_routine")
        else None,
    }
