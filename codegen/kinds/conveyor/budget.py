"""The intercept's timing budget: how far off the gripper may meet the part, term by term, against capture_mm."""

from __future__ import annotations

from dataclasses import dataclass

from codegen.controllers import get_target
from codegen.kinds.conveyor.kind import KIND
from codegen.kinds.conveyor.section import conveyor_of
from codegen.kinds.conveyor.timing import POLL_S, SPEED_WINDOW_S, lead_seconds


@dataclass(frozen=True)
class Term:
    """One source of error at the meeting point: mm = per_speed * the belt's speed + fixed."""

    what: str
    per_speed: float  # mm per mm/s of belt speed (a time, s)
    fixed: float = 0.0  # mm whatever the belt's speed

    def mm(self, speed: float) -> float:
        return self.per_speed * speed + self.fixed


def terms(cell, target: str) -> list[Term]:
    """The intercepting program's errors on a target where the gripper meets the part (mm, at a belt speed v). It
    starts down at the read of the encoder that finds the part due and lands where that read predicts the part to be
    (the read's place, its age and the lead at the speed measured): the reads' spacing adds no error of its own.
    - the count's age through the PLC and the fieldbus (count_latency_s): the program adds its middle; half
      its spread remains (v spread / 2); the arm's start after the move instruction (motion_start_s) and the
      gripper's time to hold (grip_s) likewise, their middles in the lead;
    - the speed's time, measured with the controller's timer in whole units (its timer variable: ms): one unit over the
      estimate's window, over the horizon it predicts (v horizon unit / window);
    - the count's resolution: a read in whole counts (1 / |E|);
    - the speed estimate: a difference of two reads in whole counts over the estimate's window (at most one
      count over SPEED_READS reads), over the horizon it predicts (the lead and the count's age);
    - the speed estimate: its two reads of different age (each count_latency_s old, anywhere in it: their ages differ
      by up to its spread), the time between them off by that much (v horizon spread / window);
    - the belt's speed change (belt_accel_mm_s2): the estimate is half its window and a read old when the arm starts
      down, and the speed goes on changing over the lead (a (window / 2 + read) horizon + a horizon^2 / 2)."""
    pick, e = conveyor_of(cell).pick, abs(conveyor_of(cell).counts_per_mm)
    horizon = lead_seconds(cell, get_target(target)) + pick.mean("count_latency_s")
    window = SPEED_WINDOW_S
    a = pick.belt_accel_mm_s2

    def spread(key: str) -> float:
        low, high = getattr(pick, key)
        return 0.5 * (high - low)

    # a time measured with a timer in whole units (the speed over the window's measured time): off by one unit
    unit = KIND.facts(get_target(target)).get("timer_s", 0.0)
    ages = 2.0 * spread("count_latency_s")
    return [
        Term(f"the speed's time measured in whole {unit:g} s over {window:g} s", horizon * unit / window),
        Term(f"the count's age {_span(pick.count_latency_s)} s (PLC and fieldbus)", spread("count_latency_s")),
        Term(f"the arm's start {_span(pick.motion_start_s)} s after the move", spread("motion_start_s")),
        Term(f"the gripper's hold {_span(pick.grip_s)} s", spread("grip_s")),
        Term("the count's resolution", 0.0, 1.0 / e),
        Term(f"the speed measured in whole counts over {window:g} s", 0.0, horizon / (e * window)),
        Term(f"the speed from two reads up to {ages:g} s apart in age over {window:g} s", horizon * ages / window),
        Term(
            f"the belt's speed change ({a:g} mm/s2) over the lead",
            0.0,
            a * (0.5 * window + POLL_S) * horizon + 0.5 * a * horizon**2,
        ),
    ]


def _span(interval: tuple[float, float]) -> str:
    low, high = interval
    return f"{low:g}" if low == high else f"{low:g}-{high:g}"


def total_mm(cell, target: str, speed: float | None = None) -> float:
    pick = conveyor_of(cell).pick
    v = pick.belt_speed_max_mm_s if speed is None else speed
    return sum(term.mm(v) for term in terms(cell, target))


def allowed_speed(cell, target: str) -> float:
    """The fastest belt the budget holds at within capture_mm on a target (0: none)."""
    pick = conveyor_of(cell).pick
    parts = terms(cell, target)
    fixed, slope = sum(t.fixed for t in parts), sum(t.per_speed for t in parts)
    return max(0.0, (pick.capture_mm - fixed) / slope) if slope > 0 else float("inf")


def check(ctx, cell) -> None:
    """An intercept program whose budget at the belt's fastest exceeds capture_mm is refused: the message names
    the largest terms and the belt speed the budget would hold at."""
    conveyor = conveyor_of(cell)
    if conveyor is None or conveyor.pick is None:
        return
    pick = conveyor.pick
    targets = [t for t, mode in pick.tracking.items() if mode == "intercept"]
    if not targets:
        return
    v = pick.belt_speed_max_mm_s
    for target in targets:  # each intercepting target's lead (its program's path acceleration)
        total = total_mm(cell, target)
        if total <= pick.capture_mm:
            continue
        largest = sorted(terms(cell, target), key=lambda term: term.mm(v), reverse=True)[:3]
        shown = "; ".join(f"{term.what}: {term.mm(v):.2f} mm" for term in largest)
        allowed = allowed_speed(cell, target)
        speed = f"at most {allowed:.0f} mm/s" if allowed >= 1.0 else "no belt speed"
        ctx.fail(
            "conveyor.pick.capture_mm",
            f"the intercept's timing budget ({target}) at the belt's {v:g} mm/s is {total:.2f} mm, over "
            f"capture_mm {pick.capture_mm:g} mm; largest: {shown}; within it the belt may run {speed} "
            "(belt_speed_max_mm_s)",
        )
        return
