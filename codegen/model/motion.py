"""The motion skeleton of every station from [cell.motion]: speeds and zones per segment, the retreat, the way home."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from codegen.model.loader import Loader, build
from codegen.model.schema import Key, Table

# the programs write a TCP speed to 0.1 mm/s (one controller takes it in m/s to 4 decimals): below 1 mm/s that is
# more than 5 % off, and below 0.05 mm/s the program would say 0; beyond 5000 mm/s is no programming speed
# of these arms
_SPEED = {"type": "number", "unit": "mm/s", "low": 1.0, "high": 5000.0}
# [cell.motion]: the definition the loader reads (its keys, ranges and defaults)
TABLE = Table(
    "How the arm moves through each kind's program (optional; every key has a default).",
    {
        "speed_mm_s": Key(
            **_SPEED, default=250.0, doc="TCP speed of the linear moves on the way (and RAPID's joint moves)"
        ),
        "work_speed_mm_s": Key(**_SPEED, default=50.0, doc="the last move into the work pose and the retreat from it"),
        # the largest blending zone the controllers predefine (RAPID z200)
        "zone_mm": Key(
            "number",
            "blending where the arm passes a pose (0: it stops at each; never at the work pose)",
            unit="mm",
            low=0.0,
            high=200.0,
            default=0.0,
        ),
        "retreat_mm": Key(
            "number",
            "after the work pose, back along the tool's z axis by this much (0: no retreat)",
            unit="mm",
            low=0.0,
            high=1000.0,
            default=50.0,
        ),
        "return_home": Key("boolean", "after the station, a joint move home", default=True),
        "start_tolerance_deg": Key(
            "number",
            "how far from home a program that checks where it starts lets a joint be",
            unit="deg",
            low=0.0,
            open_low=True,
            high=30.0,
            default=2.0,
        ),
        "joint_speed_percent": Key(
            "number",
            "joint moves' axis speed, percent of top speed, where a controller sets it so",
            unit="%",
            low=0.0,
            open_low=True,
            high=100.0,
            default=30.0,
        ),
    },
)
SPEED_MIN_MM_S, SPEED_MAX_MM_S = TABLE["speed_mm_s"].bounds
ZONE_MAX_MM = TABLE["zone_mm"].high


@dataclass(frozen=True)
class MotionSettings:
    """[cell.motion]: how the arm moves through a station.

    speed_mm_s: TCP speed of the linear moves between the approach and the work pose's neighbourhood
    (and RAPID's joint moves); work_speed_mm_s: the last move into the work pose and the retreat from
    it (slow); zone_mm: blending at the poses the arm passes (0: it stops at each), never at the work
    pose or a photo pose; retreat_mm: after the work pose, back along the tool's z axis by this much
    (0: no retreat); return_home: after the station, a joint move home; start_tolerance_deg: how far
    from home a program that checks where it starts (targets/<t>.toml restart = "at_home") lets a joint be."""

    speed_mm_s: float = TABLE.default("speed_mm_s")
    work_speed_mm_s: float = TABLE.default("work_speed_mm_s")
    zone_mm: float = TABLE.default("zone_mm")
    retreat_mm: float = TABLE.default("retreat_mm")
    return_home: bool = TABLE.default("return_home")
    start_tolerance_deg: float = TABLE.default("start_tolerance_deg")  # every joint this close to home
    joint_speed_percent: float = TABLE.default("joint_speed_percent")


START_TOLERANCE_MAX_DEG = TABLE["start_tolerance_deg"].high


def parse_settings(ctx, cell_table: dict) -> MotionSettings:
    """[cell.motion] of a cell file (optional), read by its declaration (TABLE); errors name the key."""
    if "motion" not in cell_table:
        return MotionSettings()
    return build(MotionSettings, Loader(ctx).table(TABLE, cell_table["motion"], "cell.motion"))


def retreat2work(retreat_mm: float) -> np.ndarray:
    """The retreat in the work pose's own frame: back along its z axis (the tool's approach direction)."""
    out = np.eye(4)
    out[2, 3] = -retreat_mm
    return out


@dataclass(frozen=True)
class Segment:
    """How the arm moves to one pose of a station's path: its TCP speed (mm/s), blending zone (mm, 0:
    it stops there), whether it must stop exactly there (the work pose, a pose where the gripper acts) and whether
    it goes at the work speed."""

    speed_mm_s: float
    zone_mm: float
    exact: bool
    slow: bool = False


def segments(
    settings: MotionSettings, taught: int, retreat: bool, stops: frozenset[int] = frozenset()
) -> list[Segment]:
    """The segments of a path of `taught` poses (the last the work pose), then the retreat: the first
    move (a joint move), the work pose and the poses in `stops` (where the gripper acts) stop exactly; the poses in
    between are passed with the zone; the moves into the work pose and into and out of a stop, and the retreat, go
    at the work speed; the retreat blends into the way home when there is one."""
    out = []
    for i in range(taught):
        exact = i == taught - 1 or i in stops
        slow = exact or (i - 1) in stops
        speed = settings.work_speed_mm_s if slow else settings.speed_mm_s
        out.append(Segment(speed, 0.0 if exact or i == 0 else settings.zone_mm, exact, slow))
    if retreat:
        out.append(Segment(settings.work_speed_mm_s, settings.zone_mm if settings.return_home else 0.0, False, True))
    return out
