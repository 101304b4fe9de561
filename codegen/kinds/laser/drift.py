"""A tool that grows along its axis while it is calibrated (warming up): the runs of the measurement disagree."""

from __future__ import annotations

import math

import numpy as np

from codegen.sim.beam_station import BeamStation
from codegen.sim.beams import Pin

# How far the tool grows per run of the measurement, in spread_max_mm: the circles alone take 2 x 2 pi circle_mm /
# circle_speed_mm_s of each run, so two runs' TCPs lie at least this many spread_max_mm apart and the farthest of
# two or more runs at least half of it from their mean: beyond spread_max_mm whatever the noise
GROWTH_PER_RUN = 3.0


def drift_mm_s(laser) -> float:
    """The growth rate (mm/s) that makes each run's TCP GROWTH_PER_RUN spread_max_mm longer than the last's."""
    circles_s = 2.0 * 2.0 * math.pi * laser.circle_mm / laser.circle_speed_mm_s
    return GROWTH_PER_RUN * laser.spread_max_mm / circles_s


class GrowingStation(BeamStation):
    """The station with a pin whose tip moves out along its axis at rate mm/s of the program's clock."""

    def __init__(self, *args, rate: float, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        self.rate, self.start = rate, self.pin.tcp2flange.copy()

    def switch(self, name: str, t: float, flange2base: np.ndarray | None) -> bool | None:
        tool = self.start.copy()
        tool[:3, 3] += tool[:3, 2] * self.rate * t
        self.pin = Pin(tool, self.pin.radius, self.pin.length)
        return super().switch(name, t, flange2base)
