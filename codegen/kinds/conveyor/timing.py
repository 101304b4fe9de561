"""The program's straight moves in time: the path acceleration it sets, a descent from standstill to standstill."""

from __future__ import annotations

import math

from codegen.kinds.conveyor.kind import KIND
from codegen.kinds.conveyor.section import conveyor_of

POLL_S = 0.012  # intercept: how often the program reads the encoder while the part comes (s)
# intercept: the belt's speed over the last SPEED_READS reads (a ring of reads, the oldest replaced by each new one):
# the error of a speed from two reads falls with the time between them (the count's age differing by up to the spread
# of count_latency_s, whole counts, whole timer units), while its age (half that time) lets a speed change through:
# 24 reads (0.288 s) make their sum least on the bundled belt (codegen/kinds/conveyor/budget.py)
SPEED_READS = 24
SPEED_WINDOW_S = SPEED_READS * POLL_S  # the first estimate of a stage: two reads this far apart (s)


def path_acc_mm_s2(target) -> float | None:
    """The path acceleration the program sets for its straight moves (mm/s2; targets/<t>.toml [program.conveyor]
    path_acc_m_s2), None where the target's program sets none (no ramp is then known)."""
    acc = KIND.facts(target).get("path_acc_m_s2")
    return None if acc is None else 1000.0 * acc


def descent_seconds(cell, target, distance: float | None = None) -> float:
    """The straight descent of approach_dz and overtravel_mm onto the part (or distance, mm) at the work speed from
    standstill to standstill: with the program's path acceleration a, d / v + v / a (a trapezoid: the ramps up and down
    add v / a), or 2 sqrt(d / a) where the descent is too short to reach v (a triangle); without one, d / v."""
    pick = conveyor_of(cell).pick
    d = pick.approach_dz + pick.overtravel_mm if distance is None else distance
    v, a = cell.motion.work_speed_mm_s, path_acc_mm_s2(target)
    if a is None:
        return d / v
    return d / v + v / a if d >= v * v / a else 2.0 * math.sqrt(d / a)


def lead_parts(cell, target) -> tuple[float, float, float]:
    """The lead's terms (s): the descent (descent_seconds), the gripper's hold (grip_s) and the program's planning
    time (motion_start_s: from its last read of the encoder to the arm moving), the intervals' middles."""
    pick = conveyor_of(cell).pick
    return descent_seconds(cell, target), pick.mean("grip_s"), pick.mean("motion_start_s")


def lead_seconds(cell, target) -> float:
    """How long before the part reaches the intercept point an intercepting arm starts down: the descent of
    approach_dz at the work speed with the program's path acceleration, the arm's start after the move
    instruction and the gripper's time to hold the part once its output is set (the middles of motion_start_s
    and grip_s)."""
    return sum(lead_parts(cell, target))
