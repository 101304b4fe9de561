"""Template variables of source 003's automatic TCP program: sensor frame, circles, search, names verify reads."""

# The program (every controller the same way; templates/<t>/laser.*.j2):
# 1. Home, the cell's tool (its data is the guess), the TCP's orientation in the sensor frame S `down`
#    (the flange's z along S's -z).
# 2. Per circle k (depth d_k): straight to `above` (S z = +clearance), down to `start` (45 deg between the
#    beams, the guessed tip d_k below their plane), each beam's switching output watched on both edges,
#    two half circles (via `via1` to `mid`, via `via2` back to `start`) at the circle speed, then back up.
#    Each edge stores the TCP where the controller saw it (S): beam X (the line y = 0) the y, beam Y the x;
#    exactly four per beam (two crossings, in and out), else the program stops with CIRCLE_EDGES.
# 3. The circle's centre e_k = -(mean of beam Y's four x, mean of beam X's four y): where the axis met the
#    beams' plane with the guessed tip at S's origin (edges in and out lie symmetric about the axis: the pin's
#    radius and the hysteresis cancel; a late cycle on one crossing is opposite on the other: the mean keeps
#    it small). The axis u = (s_x, s_y, 1) / |(s_x, s_y, 1)|, s = (e_2 - e_1) / (d_2 - d_1)
#    (identity laser_axis_from_two_centres); a slope beyond 2 offset_max / (d_2 - d_1) stops (AXIS_TILT).
# 4. The tip: the guessed tip at (-e_1, -d_1) puts the axis through S's origin; along u to clearance above the
#    plane (`top`), a search along -u to clearance below (`bottom`) for beam X switching on, then back up for
#    it switching off; the mean of the two is the contact (no edge: NO_TIP). There the end face's rim touches
#    the beam: the tip is rho |u_x| u_z / sqrt(1 - u_x^2) above it (identity laser_tip_on_beam), on the axis:
#    tip = u rim / u_z.
# 5. TCP (flange frame) = guess + DOWN (tip - contact), DOWN = diag(1, -1, -1) (the flange's orientation in S);
#    farther than offset_max from the guess: TOO_FAR, not written; else written into the tool's data (the
#    controller's own tool for this tool) and reported.

from __future__ import annotations

import math

import numpy as np

from codegen.emit import EmitError, Emitter, owned
from codegen.kinds.laser.facts import facts
from codegen.kinds.laser.section import laser_of
from codegen.model.cell import TaughtPose
from codegen.poses import zyx_deg_from_rotmat

DOWN = np.diag([1.0, -1.0, -1.0])
# the operator's messages: within 80 characters with their numbers (the shortest controller message, string_max)
CIRCLE_EDGES = "laser: beams not crossed twice each, check tool data and sensors, circle "
NO_TIP = "laser: no tip found within clearance_mm of the tool data"
AXIS_TILT = "laser: axis tilted beyond offset_max_mm, check the sensors"
TOO_FAR = "laser: TCP beyond offset_max_mm of the tool data, not written"
WRITTEN = "laser: TCP written, flange frame mm: "
EDGES_PER_BEAM = 4


def laser_ident(cell, target) -> str:
    return Emitter(target).identifier("tcp_", cell.name, "the laser TCP program")


def laser_file_names(cell, target) -> list[str]:
    ident = laser_ident(cell, target).lower()
    return [name.format(laser=ident) for name in facts(target).get("files", [])]


def calibrates_on(cell, target) -> bool:
    """Whether the cell has a laser TCP program for this target."""
    if laser_of(cell) is None:
        return False
    if not facts(target).get("files"):
        raise EmitError(f"laser: codegen has no laser TCP program for {target.title}")
    return True


def circle_points(laser, k: int) -> dict[str, tuple[float, float, float]]:
    """Circle k's poses' positions in S (mm): above, start, via1, mid, via2 (counterclockwise from 45 deg)."""
    h = laser.circle_mm / math.sqrt(2.0)
    z = -laser.depths_mm[k]
    return {
        "above": (h, h, laser.clearance_mm),
        "start": (h, h, z),
        "via1": (-h, h, z),
        "mid": (-h, -h, z),
        "via2": (h, -h, z),
    }


def kept_names(target) -> dict[str, str]:
    """The program's globals verify reads when the run ends (targets/<t>.toml laser_names)."""
    return dict(facts(target)["names"])


def _xyzabc(matrix: np.ndarray) -> tuple[float, ...]:
    return tuple(float(v) for v in (*matrix[:3, 3], *zyx_deg_from_rotmat(matrix[:3, :3])))


def laser_context(cell, target, emitter: Emitter) -> dict:
    laser = laser_of(cell)
    number = emitter.number
    guess = cell.robot.tool.tcp2flange
    down = np.eye(4)
    down[:3, :3] = DOWN @ guess[:3, :3]
    circles = []
    for k in (0, 1):
        circles.append({name: [number(v, 4) for v in xyz] for name, xyz in circle_points(laser, k).items()})
    dz = laser.depths_mm[1] - laser.depths_mm[0]
    return {
        "ident": emitter.identifier("tcp_", cell.name, "the laser TCP program"),
        "sensor": emitter.pose(laser.sensor_frame),
        "down": emitter.pose(TaughtPose("down", _xyzabc(down), "xyzabc")),
        "guess": [number(v, 4) for v in guess[:3, 3]],
        "circles": circles,
        "depths": [number(v, 4) for v in laser.depths_mm],
        "dz": number(dz, 4),
        "clearance": number(laser.clearance_mm, 4),
        "radius": number(laser.pin_radius_mm, 4),
        "offset_max": number(laser.offset_max_mm, 4),
        "slope_max": number(2.0 * laser.offset_max_mm / dz, 6),
        "circle_speed": number(laser.circle_speed_mm_s, 3),
        "search_speed": number(laser.search_speed_mm_s, 3),
        "edges": EDGES_PER_BEAM,
        "beam_x": emitter.signal_ref("input", laser.beam_x[target.name], f"laser.beam_x.{target.name}"),
        "beam_y": emitter.signal_ref("input", laser.beam_y[target.name], f"laser.beam_y.{target.name}"),
        "beam_x_raw": emitter.signal(laser.beam_x[target.name], f"laser.beam_x.{target.name}"),
        "beam_y_raw": emitter.signal(laser.beam_y[target.name], f"laser.beam_y.{target.name}"),
        "names": owned(kept_names(target)),
        "circle_edges": emitter.string(CIRCLE_EDGES),
        "no_tip": emitter.string(NO_TIP),
        "axis_tilt": emitter.string(AXIS_TILT),
        "too_far": emitter.string(TOO_FAR),
        "written": emitter.string(WRITTEN),
    }
