"""The program's straight moves in time: the path acceleration it sets, a descent from standstill to standstill."""

from __future__ import annotations

import math

from codegen.kinds.conveyor.kind import KIND
from codegen.kinds.conveyor.section import conveyor_of


def path_acc_mm_s2(target) -> float | None:
    """The path acceleration the program sets for its straight moves (mm/s2; targets/<t>.toml [program.conveyor]
    path_acc_m_s2), None where the target's program sets none (no ramp is then known)."""
    acc = KIND.facts(target).get("path_acc_m_s2")
    return None if acc is None else 1000.0 * acc


def descent_seconds(cell, target, distance: float | None = None) -> float:
    """The straight descent of approach_dz (or distance, mm) at the work speed from standstill to standstill: with
    the program's path acceleration a, d / v + v / a (a trapezoid: the ramps up and down add v / a), or 2 sqrt(d / a)
    where the descent is too short to reach v (a triangle); without one, d / v."""
    d = conveyor_of(cell).pick.approach_dz if distance is None else distance
    v, a = cell.motion.work_speed_mm_s, path_acc_mm_s2(target)
    if a is None:
        return d / v
    return d / v + v / a if d >= v * v / a else 2.0 * math.sqrt(d / a)
