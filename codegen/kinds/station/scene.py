"""The station kind's objects in the cell's page: each station as its mode draws it."""

from __future__ import annotations

from codegen import protocol
from codegen.kinds.station.mode import modes
from codegen.kinds.station.section import stations_of


class ScenePart(protocol.Scene):
    def objects(self, cell) -> list[dict]:
        return [o for station in stations_of(cell) for o in modes()[station.mode].station_scene(cell, station)]
