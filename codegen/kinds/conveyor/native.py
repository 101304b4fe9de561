"""Native tracking's settings: UR's trigger input; ABB's Conveyor Tracking option (the belt as a mechanical unit,
the coordinated work object, the queue's configuration the integrator enters), one source for the program's text
and for the simulated controller verify runs it on."""

from __future__ import annotations

import numpy as np

from codegen.emit import owned
from codegen.kinds.conveyor.kind import KIND
from codegen.kinds.conveyor.reach import follow_mm
from codegen.kinds.conveyor.section import conveyor_of
from codegen.model.cell import TaughtPose
from codegen.poses import zyx_deg_from_rotmat
from codegen.sim.belt import UnitSettings

# The coordinated work object's object frame in its user frame, the unit's frame (x along the travel, z up: the
# controller takes a coordinated work object's user frame from the unit's system parameters, not from the program's
# uframe): turned -90 deg about z, so that the program's coordinates are the belt frame's (x across the belt, y along
# the travel, z up).
BELT_IN_UNIT = np.array([[0.0, 1.0, 0.0, 0.0], [-1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0]])


def unit_frame(cell) -> np.ndarray:
    """The unit's base frame as the option wants it (base frame, 4x4): at the sync point (the camera's line), x
    along the travel, z the belt's normal."""
    belt = conveyor_of(cell)
    out = belt.frame() @ np.linalg.inv(BELT_IN_UNIT)
    out[:3, 3] = np.asarray(belt.origin) - belt.camera_offset_mm * np.asarray(belt.direction)
    return out


def settings(cell, target) -> UnitSettings:
    """The mechanical unit's configuration (system parameters) the program needs: counts per metre (a whole
    number), the queue tracking distance (the sync point to the start window: the camera's line to the window's
    start), the start window's width (the pick window), the minimum distance between two parts, the tracking
    range's end (the window's end and as far as the arm may follow a part past it)."""
    belt, pick = conveyor_of(cell), conveyor_of(cell).pick
    start, end = pick.window_mm
    return UnitSettings(
        name=pick.unit[target.name],
        counts_per_m=round(abs(belt.counts_per_mm) * 1000.0),
        frame=unit_frame(cell),
        start_mm=belt.camera_offset_mm + start,
        width_mm=end - start,
        min_gap_mm=pick.min_gap_mm,
        max_mm=belt.camera_offset_mm + end + follow_mm(cell, target.name),
        remove_all=_remove_all(cell, target),
        axis=pick.unit_axis[target.name],
    )


def _remove_all(cell, target) -> str | None:
    """The unit's signal that empties its queue (targets/<t>.toml [program.conveyor] unit_signals), by its name."""
    pattern = KIND.facts(target).get("unit_signals", {}).get("remove_all")
    name = conveyor_of(cell).pick.unit[target.name]
    return None if pattern is None else pattern.format(n=_number(name))


def margin_mm(cell) -> float:
    """How far past the window's end a part must be, by the PLC's count, before the program takes it as gone from
    the unit's queue too: two counts and the count's age at the belt's fastest."""
    pick = conveyor_of(cell).pick
    return 2.0 / abs(conveyor_of(cell).counts_per_mm) + pick.belt_speed_max_mm_s * pick.count_latency_s[1]


def sync_tol_mm(cell, target) -> float:
    """How far the connected object's position (the unit's count since its sync) may lie from the part's travel by
    the PLC's count and still be the same part: the margin (two counts, the count's age at the belt's fastest), two
    counts more (each side reads a whole count) and the unit's whole counts per metre against the belt's scale over
    the tracking range (half a count per metre at most); at least half the Sync Separation (min_gap_mm: the unit
    queues no other object nearer to this one than that, so a larger difference is another object)."""
    unit = settings(cell, target)
    per_mm = abs(conveyor_of(cell).counts_per_mm)
    measured = margin_mm(cell) + 2.0 / per_mm + unit.max_mm * 0.5 / unit.counts_per_m
    return max(measured, 0.5 * unit.min_gap_mm)


def connect_s(cell, target) -> float:
    """WaitWObj's \\MaxTime: the part crosses the tolerance at the belt's fastest in this time, at least 0.1 s (the
    program waits again while the PLC's count says the part is still within the tolerance of the window's start)."""
    return max(0.1, sync_tol_mm(cell, target) / conveyor_of(cell).pick.belt_speed_max_mm_s)


def _pose(emitter, matrix: np.ndarray, name: str) -> list[str]:
    values = (*matrix[:3, 3], *zyx_deg_from_rotmat(matrix[:3, :3]))
    return emitter.pose(TaughtPose(name, tuple(float(v) for v in values), "xyzabc"))


def _number(unit: str) -> str:
    """The unit's number in its signals' prefix (CNV1: c1...; a name without one: 1)."""
    digits = unit[len(unit.rstrip("0123456789")) :]
    return digits or "1"


def context(cell, target, emitter) -> dict:
    """The native program's own template variables."""
    pick = conveyor_of(cell).pick
    out: dict = {"trigger": None, "unit": None}
    if target.name in pick.trigger_input:
        out["trigger"] = emitter.number(pick.trigger_input[target.name], 0)
    if target.name in pick.unit:
        unit = settings(cell, target)
        number = emitter.number
        out["unit"] = {
            "name": emitter.reserve(unit.name, "the belt's mechanical unit"),  # one of the facts' units
            "frame": _pose(emitter, unit.frame, "unit"),
            "oframe": _pose(emitter, BELT_IN_UNIT, "oframe"),
            "counts_per_m": number(unit.counts_per_m, 0),
            "start_mm": number(unit.start_mm, 1),
            "width_mm": number(unit.width_mm, 1),
            "min_gap_mm": number(unit.min_gap_mm, 1),
            "max_mm": number(unit.max_mm, 1),
            "margin_mm": number(margin_mm(cell), 3),
            "signals": {
                key: emitter.reserve(name.format(n=_number(unit.name)), "a signal of the option")
                for key, name in KIND.facts(target).get("unit_signals", {}).items()
            },
            "counts_down": conveyor_of(cell).counts_per_mm < 0,
            "axis": unit.axis,
            # the generator's own text: the extjoint component of the logical axis, and extax with 0 there
            "slot": owned("eax_" + "abcdef"[unit.axis - 7]),
            "extax": owned("[" + ", ".join("0" if i == unit.axis - 7 else "9E+09" for i in range(6)) + "]"),
            "sync_tol_mm": number(sync_tol_mm(cell, target), 3),
            "position_check": pick.unit_position_check,
            "connect_s": number(connect_s(cell, target), 3),
            "drop_settle_s": number(KIND.facts(target)["drop_settle_s"], 3),
        }
    return out
