"""The station kind in the cell: each station as its mode draws it, and the arm's planned way through each station
(nominal and at the correction region's corners) for the clearance proof."""

from __future__ import annotations

import numpy as np

from codegen.kinds.station.keys import GRIP
from codegen.kinds.station.mode import mode_of
from codegen.world.cell import shape_of
from codegen.world.proof import Move, Path

# the readings proven clear beside the nominal one: the largest shift along these directions (deg from +x) at the
# largest rotation of this sign: each direction once, each rotation twice (the region's corners)
CORNERS = ((0.0, 1.0), (90.0, -1.0), (180.0, 1.0), (270.0, -1.0))


def corners(offsets: np.ndarray) -> list[int]:
    """The rows of the region's readings (codegen.kinds.station.region.offsets) proven clear: nothing moved (row 0)
    and the CORNERS (the nearest sampled readings)."""
    shift = np.hypot(offsets[:, 0], offsets[:, 1])
    rotation = offsets[:, 2]
    out = [0]
    if len(offsets) < 2:
        return out
    outer = np.isclose(shift, shift.max())
    angles = np.degrees(np.arctan2(offsets[:, 1], offsets[:, 0]))
    for direction, sign in CORNERS:
        turn = rotation.max() if sign > 0 else rotation.min()
        rows = np.flatnonzero(outer & np.isclose(rotation, turn))
        gap = np.abs((angles[rows] - direction + 180.0) % 360.0 - 180.0)
        out.append(int(rows[int(np.argmin(gap))]))
    return sorted(set(out))


def _reading(offset) -> str:
    dx, dy, rot = (float(v) for v in offset)
    return "nominal reading" if not (dx or dy or rot) else f"reading {dx:+.1f}, {dy:+.1f} mm, {rot:+.1f} deg"


def station_paths(cell, target: str, station, region) -> list[Path]:
    """The station's program on the target's arm from home, for each proven reading: the moves through the station's
    arm poses (a joint move, then linear ones, as its mode plans them) over its correction region
    (codegen/kinds/station/region.py StationRegion), then home where the cell returns there; the part held from a grip
    to the next release ([station.gripper]), and from the start where its first action is a release."""
    mode = mode_of(station)
    arm_poses = mode.arm_poses(cell, station)
    rows = corners(region.offsets)
    tcp = mode.region(cell, station, region.offsets[rows])
    nominal = mode.region(cell, station, region.offsets[:1])[0]
    home = np.asarray(cell.robot.home[target], dtype=float)
    out = []
    for n, row in enumerate(rows):
        reading = _reading(region.offsets[row])
        held = bool(station.holds_at_start)
        moves = []
        for m, (name, _tcp, motion) in enumerate(arm_poses):
            action = station.action(name) or ""
            where = f"station {station.id} {station.name!r} pose {name!r} ({reading})"
            moves.append(Move(motion, region.joints[row, m], where, tcp[n, m], held, grip=action))
            if action:
                held = action == GRIP
        if cell.motion.return_home:
            where = f"station {station.id} {station.name!r} the way home ({reading})"
            moves.append(Move("joint", home, where, carrying=held))
        moved = _motion(tcp[n], nominal)
        # a station whose configuration the cell does not name has been tried in every one that reaches
        # (posture.py): the one named there is the cell's own choice
        configuration = f"[station.config.{target}]: where a station names none, each that reaches has been tried"
        out.append(
            Path(target, home, tuple(moves), station.part, {"": station_solids(station, moved)}, configuration)
        )
    return out


def _motion(poses: np.ndarray, nominal: np.ndarray) -> np.ndarray:
    """The base-frame motion a reading applies to the station (its machine moves with its mark, as its poses do):
    that of the first pose the reading moves (a pose on the robot's own carrier stays), none where none moves."""
    for pose, at in zip(poses, nominal, strict=True):
        motion = pose @ np.linalg.inv(at)
        if not np.allclose(motion, np.eye(4), atol=1e-9):
            return motion
    return np.eye(4)


def case_motion(cell, station, reading) -> np.ndarray:
    """The base-frame motion a verify case's reading applies to the station (as _motion: its path's poses as the
    reference moves the arm through them, against the nominal ones); none where the reference does not reach the
    station's path."""
    mode = mode_of(station)
    trace = mode.accepted(cell, reading)[0][0]
    count = len(station.path)
    nominal = mode.region(cell, station, np.zeros((1, 3)))[0][-count:]
    poses = [move.tcp2base for move in trace.moves[trace.path_start : trace.path_start + count]]
    if trace.status != "ok" or len(poses) != count or any(p is None for p in poses):
        return np.eye(4)
    return _motion(np.array(poses), nominal)


def station_solids(station, moved: np.ndarray | None = None) -> dict:
    """The station's [station.solids] in the base frame, moved by a reading's base-frame motion (None: as declared),
    by names unique in the cell (the station's name first)."""
    return {f"{station.name}: {name}": shape_of(spec, moved) for name, spec in station.solids.items()}
