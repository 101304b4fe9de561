"""The two crossed beams in the cell: as the page draws them (the sensor frame, the beams, the sensors) and the
sensors' housings as solids."""

from __future__ import annotations

from dataclasses import fields

import numpy as np

from codegen import protocol
from codegen.sim.beams import Sensors
from codegen.view.scene import box, frame, line, point, translated
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


class ScenePart(protocol.Scene):
    def objects(self, cell) -> list[dict]:
        section = self.kind.section.of(cell)
        return [] if section is None else objects(cell, section)

    def solids(self, cell) -> dict[str, Box]:
        section = self.kind.section.of(cell)
        return {} if section is None else solids(section)
