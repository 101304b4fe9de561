"""The station kind's scene part: the stations as drawn, a case's station's solids, the paths generate proves."""

from __future__ import annotations

import numpy as np

from codegen import protocol
from codegen.kinds.station.mode import modes
from codegen.kinds.station.plan import Plan
from codegen.kinds.station.scene import case_motion, station_paths, station_solids
from codegen.kinds.station.section import section_of, stations_of
from codegen.protocol import Stage
from codegen.world.proof import Path


class ScenePart(protocol.Scene):
    def objects(self, cell) -> list[dict]:
        return [o for station in stations_of(cell) for o in modes()[station.mode].station_scene(cell, station)]

    def carried(self, cell):
        """The first station's part that gives one ([station.part]); a case's own station's in staged."""
        return next((s.part for s in stations_of(cell) if s.part is not None), None) if section_of(cell) else None

    def staged(self, cell, target: str, case):
        """The case's station's own solids moved by its reading (the other stations' machines are not where the arm
        works: each stands at its own station), its part in the gripper."""
        section, reading = section_of(cell), getattr(case, "reading", None)
        station = None if section is None else section.station_by_id(getattr(reading, "station_id", None))
        if station is None:  # an unknown station's case (or none): the program stops before it moves there
            return super().staged(cell, target, case)
        if not station.solids:
            stage = Stage((station.id,), {}, station.part)
        else:
            motion = case_motion(cell, station, reading)
            key = (station.id, *np.round(motion[:3].ravel(), 9).tolist())
            stage = Stage(key, station_solids(station, motion), station.part)
        return lambda _grips, _releases: stage

    def paths(self, cell, targets: list[str]) -> list[Path]:
        if cell.robot is None or section_of(cell) is None:
            return []
        out = []
        for target in [t for t in targets if t in cell.robot.arms]:
            planned = self.kind.plan(cell, target)  # the configuration of each station handed down with the cell
            out += [path for station in planned.stations for path in _paths(planned, station)]
        return out

    def proven(self, cell, target: str) -> list | None:
        """Each station's paths as the posture's choice proved them (the plan's), the others proven here."""
        from codegen.world.proof import prove  # coal: loaded only when proving

        if cell.robot is None or target not in cell.robot.arms or section_of(cell) is None:
            return []
        planned = self.kind.plan(cell, target)
        out = []
        for station in planned.stations:
            out += station.proven if station.proven is not None else prove(cell, _paths(planned, station))
        return out


def _paths(planned: Plan, station) -> list[Path]:
    """The station's paths on the plan's target in its configuration there (ReachError: its pose has no solution)."""
    return station_paths(planned.cell, planned.target, station.station, station.solved())
