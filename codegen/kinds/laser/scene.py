"""The two crossed beams in the cell: as the page draws them (the sensor frame, the beams, the sensors) and the
sensors' housings as solids."""

from __future__ import annotations

from dataclasses import fields

import numpy as np

from codegen import protocol
from codegen.sim.beams import Sensors
from codegen.view.scene import box, frame, line, point, translated
from codegen.world.proof import FROM_THE_HOME, Move, Path
from codegen.world.solids import Box

REACH_MM = next(f.default for f in fields(Sensors) if f.name == "reach")  # each sensor to the crossing
BODY_MM = (40.0, 30.0, 30.0)  # a sensor's body as drawn (along its beam first)


def _sensors(laser) -> list[tuple[str, np.ndarray, tuple[float, float, float]]]:
    """Each sensor's name, body pose (base frame) and size: at -reach along its beam, the body behind its lens."""
    sensor2base = laser.sensor_frame.matrix()
    out = []
    for name, axis in (("X", np.array([1.0, 0.0, 0.0])), ("Y", np.array([0.0, 1.0, 0.0]))):
        body = translated(sensor2base, -(REACH_MM + BODY_MM[0] / 2) * axis)
        out.append((name, body, BODY_MM if name == "X" else (BODY_MM[1], BODY_MM[0], BODY_MM[2])))
    return out


def solids(laser) -> dict[str, Box]:
    """The two sensors' housings (as drawn: BODY_MM behind each lens)."""
    return {f"sensor {name}": Box(size, body) for name, body, size in _sensors(laser)}


def objects(cell, laser) -> list[dict]:
    """The sensor frame S, its two beams crossing at S's origin (X along +x from its sensor at -x, Y along +y from
    its sensor at -y, as codegen.sim.beams has them) and the two sensors."""
    sensor2base = laser.sensor_frame.matrix()
    out = [frame(sensor2base, "sensor frame S", "sensor", 50.0)]
    axes = (np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0]))
    for axis, (name, body, size) in zip(axes, _sensors(laser), strict=True):
        ends = [sensor2base @ np.array([*(s * REACH_MM * axis), 1.0]) for s in (-1.0, 1.0)]
        out.append(line(ends, "beam", f"beam {name}"))
        out.append(box(body, size, "sensor", f"sensor {name}"))
    out.append(point(sensor2base[:3, 3], "beam", "crossing"))
    return out


def laser_paths(cell, target: str) -> list[Path]:
    """The calibration on the target's arm as its reach proof plans it: from home a joint move to the safe pose,
    then straight moves through every pose (each circle as CIRCLE_STEPS chords), home; and a start after a stop at
    the lowest pose (the tip search's bottom), backing out straight up to the safe height, to the safe pose and home.
    Joints: from home the solution nearest the pose before, in one configuration throughout."""
    from codegen.kinds.laser.reach import path as reach_path
    from codegen.kinds.laser.section import laser_of
    from codegen.robot import solve

    robot = cell.robot
    arm = robot.arms[target]
    home = np.asarray(robot.home[target], dtype=float)
    planned = reach_path(cell)
    flange = solve.flange_poses(np.array([p for _w, p in planned]), robot.tool.tcp2flange)
    q, joints = home, []
    for sols in solve.branches(arm, flange):
        q, _ = solve.nearest(arm, sols, q)
        joints.append(q)
    moves = [
        Move("joint" if i == 0 else "linear", joints[i], f"laser station: {what}", pose)
        for i, (what, pose) in enumerate(planned)
    ]
    moves.append(Move("joint", home, "laser station: home"))
    out = [Path(target, home, tuple(moves), configuration=FROM_THE_HOME)]
    low = min(range(len(planned)), key=lambda i: planned[i][1][2, 3])
    axis = laser_of(cell).sensor_frame.matrix()[:3, 2]  # S's z: straight up out of the column
    up = planned[low][1].copy()
    up[:3, 3] += axis * float(axis @ (planned[0][1][:3, 3] - up[:3, 3]))
    flange_up = solve.flange_poses(up[None], robot.tool.tcp2flange)
    q_up, _ = solve.nearest(arm, solve.branches(arm, flange_up)[0], joints[low])
    start = (
        Move("linear", q_up, f"laser station: a start at {planned[low][0]}: straight up to the safe height", up),
        Move("linear", joints[0], "laser station: a start in the column: the safe pose", planned[0][1]),
        Move("joint", home, "laser station: a start in the column: home"),
    )
    out.append(Path(target, joints[low], start, configuration=FROM_THE_HOME))
    return out


class ScenePart(protocol.Scene):
    def objects(self, cell) -> list[dict]:
        section = self.kind.section.of(cell)
        return [] if section is None else objects(cell, section)

    def solids(self, cell) -> dict[str, Box]:
        section = self.kind.section.of(cell)
        return {} if section is None else solids(section)

    def paths(self, cell, targets: list[str]) -> list[Path]:
        if self.kind.section.of(cell) is None or cell.robot is None:
            return []
        return [path for t in targets if t in cell.robot.arms for path in laser_paths(cell, t)]
