"""Template variables of source 003's automatic TCP program: sensor frame, circles, search, names verify reads."""

# The program (every controller the same way; templates/<t>/laser.*.j2):
# 0. The start: the cell's tool as designed ([cell.tool]: its data is the guess) is the tool of every move. The
#    arm at home, or else in the station's column above the sensors (S's z between ZONE_LOW and ZONE_HIGH, at most
#    ZONE_R from S's z axis: every pose the calibration takes, with room for a stop): a calibration stopped there
#    backs out straight up (S's z: the tool's axis in every pose of the calibration) to the safe height, goes to
#    the safe pose and home. Anywhere else it stops before it moves (START_AWAY): no path from there is known.
# 1. Home, the safe pose (`safe`: safe_height_mm straight above the circles' start, the flange's z along S's -z),
#    blended into the way down (where the target blends joint moves), then above the start, blended.
# 2. Per circle k (depth d_k): down to `start` (45 deg between the beams, the guessed tip d_k below their plane),
#    each beam's switching output watched on both edges, two half circles (via `via1` to `mid`, via `via2` back to
#    `start`) at the circle speed, then back up to `above` (exact: the count decides what follows).
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
#    farther than offset_max from the tool as designed (never the last result: a tool that bends a little each
#    time must not drift without an alarm): TOO_FAR, not written. Steps 2-5 run `runs` times (back above the start
#    between runs), each run's TCP kept; the TCP is their mean; a run farther than spread_max from it: SPREAD,
#    not written (the measurement does not repeat: a loose pin, a sensor or tool drifting); else written into the
#    production tool (the cell's [laser] production_tool) and reported. Then the safe pose and home.

from __future__ import annotations

import math

import numpy as np

from codegen.emit import Code, EmitError, Emitter, owned
from codegen.kinds.laser.kind import KIND
from codegen.kinds.laser.section import laser_of, production_tool
from codegen.model.cell import TaughtPose
from codegen.poses import zyx_deg_from_rotmat

DOWN = np.diag([1.0, -1.0, -1.0])
# the operator's messages: within 80 characters with their numbers (each target's message text holds 80;
# tests/kinds/test_laser_production.py holds every one to its controller's string_max with the longest numbers)
CIRCLE_EDGES = "laser: beams not crossed twice each, check tool data and sensors, circle "
NO_TIP = "laser: no tip found within clearance_mm of the tool data"
AXIS_TILT = "laser: axis tilted beyond offset_max_mm, check the sensors"
TOO_FAR = "laser: TCP beyond offset_max_mm of the tool as designed, not written"
WRITTEN = "laser: TCP written, flange frame mm: "
START_AWAY = "laser: start with the arm at home or above the sensors"
SPREAD = "laser: runs differ beyond spread_max_mm, TCP not written"
SPREAD_SEEN = "laser: runs' spread mm (farthest run from their mean): "  # logged on every calibration
BEFORE = "laser: production tool before, flange frame mm: "  # where a target's program shows the tool it replaces
NUMBER_MAX = "-2000.000"  # the widest number a message carries: a TCP within 2,000 mm of the flange, 3 decimals
EDGES_PER_BEAM = 4


def laser_ident(cell, target) -> str:
    return Emitter(target).identifier("tcp_", cell.name, "the laser TCP program")


def data_ident(cell, target) -> str:
    """The module that declares the production tool where a target's program needs one (RAPID's system module)."""
    return Emitter(target).identifier("tcp_", f"{cell.name}_tool", "the production tool's data module")


def laser_file_names(cell, target) -> list[str]:
    ident, data = laser_ident(cell, target).lower(), data_ident(cell, target).lower()
    return [name.format(laser=ident, data=data) for name in KIND.facts(target).get("files", [])]


def production_name(cell, target) -> str:
    """The production tool as the program names it: TOOL_DATA[3], tPin, pin_tcp."""
    spec = KIND.facts(target)["production_tool"]
    value = production_tool(cell, target.name)
    return spec["name"].format(n=value, name=value)


def production_code(cell, target, emitter: Emitter) -> Code:
    """The production tool as the program writes it: the controller's numbered tool (the target's pattern around
    the cell's number), or the cell's name of data the controller has, written as it is (emitter.given_name: a
    word or predefined name of the language, or one of the program's own, is refused)."""
    spec = KIND.facts(target)["production_tool"]
    value = production_tool(cell, target.name)
    if spec["form"] == "number":
        return emitter.numbered(spec["name"], value, f"laser.production_tool.{target.name}")
    return emitter.given_name(value, f"laser.production_tool.{target.name}", "tool")


def safe_point(laser) -> tuple[float, float, float]:
    """The safe pose's position in S (mm): safe_height_mm straight above the circles' start."""
    h = laser.circle_mm / math.sqrt(2.0)
    return (h, h, laser.safe_height_mm)


def zone(laser) -> dict[str, float]:
    """The station's column in S where a stopped calibration may back out (mm): every pose the program takes lies
    at most `r` from S's z axis (the circles circle_mm; the search's line within offset_max_mm of S's origin at
    the plane, tilted at most 2 offset_max_mm / (d_2 - d_1) up to d_1 + clearance_mm away from it) and between
    `low` and `high` (the deepest circle or the search's bottom, the safe height); offset_max_mm more on each
    side for the stopping distance of a move near the sensors (a few mm at most)."""
    slope = 2.0 * laser.offset_max_mm / (laser.depths_mm[1] - laser.depths_mm[0])
    search = laser.offset_max_mm + slope * (laser.depths_mm[0] + laser.clearance_mm)
    margin = laser.offset_max_mm
    return {
        "r": max(laser.circle_mm, search) + margin,
        "low": -max(laser.depths_mm[1], laser.clearance_mm) - margin,
        "high": laser.safe_height_mm + margin,
    }


def calibrates_on(cell, target) -> bool:
    """Whether the cell has a laser TCP program for this target."""
    if laser_of(cell) is None:
        return False
    if not KIND.facts(target).get("files"):
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
    return dict(KIND.facts(target)["names"])


def _xyzabc(matrix: np.ndarray) -> tuple[float, ...]:
    return tuple(float(v) for v in (*matrix[:3, 3], *zyx_deg_from_rotmat(matrix[:3, :3])))


def saved_name(cell, target) -> str | None:
    """Where verify reads the production tool as its module's saved file keeps it (None: no module saved)."""
    spec = KIND.facts(target).get("saved")
    if spec is None:
        return None
    return spec["kept"].format(module=data_ident(cell, target), name=production_name(cell, target))


def _save_path(cell, target, emitter: Emitter) -> Code | None:
    spec = KIND.facts(target).get("saved")
    return None if spec is None else emitter.string(spec["path"].format(module=data_ident(cell, target)))


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
    column = zone(laser)
    return {
        "ident": emitter.identifier("tcp_", cell.name, "the laser TCP program"),
        "data_ident": emitter.identifier("tcp_", f"{cell.name}_tool", "the production tool's data module")
        if any("{data}" in pattern for pattern in KIND.facts(target)["files"])
        else None,
        # the entry routine where the program is a module of the production task (whose main is its own)
        "entry": emitter.identifier("tcp_", f"{cell.name}_run", "the laser TCP program's entry routine")
        if KIND.facts(target).get("entry_routine")
        else None,
        "production": production_code(cell, target, emitter),
        "save_path": _save_path(cell, target, emitter),
        "asks_within_s": None if (within := KIND.facts(target).get("asks_within_s")) is None else number(within, 1),
        "safe": [number(v, 4) for v in safe_point(laser)],
        "safe_height": number(laser.safe_height_mm, 4),
        "zone_r": number(column["r"], 4),
        "zone_low": number(column["low"], 4),
        "zone_high": number(column["high"], 4),
        "joint_zone": bool(KIND.facts(target)["joint_zone"]),
        "blend": cell.motion.zone_mm > 0,
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
        "start_away": emitter.string(START_AWAY),
        "spread": emitter.string(SPREAD),
        "spread_seen": emitter.string(SPREAD_SEEN),
        "runs": laser.runs,
        "spread_max": number(laser.spread_max_mm, 4),
        "before": emitter.string(BEFORE),
    }
