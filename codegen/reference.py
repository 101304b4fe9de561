"""The expected trace of a correct program: what every kind's float64 reference produces."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

JOINT = "joint"
LINEAR = "linear"


@dataclass(frozen=True)
class Move:
    kind: str  # JOINT or LINEAR
    pose_name: str
    tcp2base: np.ndarray = field(compare=False)
    exact: bool = False  # the arm must stop at this pose (a work or photo pose): no blending


@dataclass(frozen=True)
class ExpectedTrace:
    """Expected behaviour of a correct program for one case."""

    status: str  # "ok" or "halt"
    reason: str | None = None  # a codegen.guard halt reason
    station: Any = None  # codegen.cell.Station, or None for an unknown station
    moves: tuple[Move, ...] = ()
    logged: tuple[float, ...] | None = None  # the numbers of the program's log line(s), in order
    detail: Any = None  # the kind's own figures (kinds/<kind>.py), e.g. the correction or the photos
