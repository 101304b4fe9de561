"""The belt's verify cases: the parts, the belt's speed and counter, the scenarios each target is tried in."""

from __future__ import annotations

import math
import random
from dataclasses import dataclass, replace

from codegen.kinds.conveyor.program import LATCH_RING
from codegen.kinds.conveyor.section import conveyor_of
from codegen.sim.belt import Belt, Part

PAST_END_MM = 40.0  # the part_past_the_window case: this far past the window's end when the program reads it
DECISION_S = 1.0  # about when the program first reads the queue (after its home move and the gripper's release)
COUNTER_BITS = 16  # the count the program reads: UR's filtered count [0; 65536[ (URScript manual), a 16-bit group
SCENARIOS = {
    "start_away": "",
    "start_mid_cycle": "",  # the arm where a stop after a grip left it: above the belt, holding the part
    "gripper_silent": "",
    "gripper_stuck": "",
    "device_late": "the belt's parts come at random gaps, speeds and a varying speed in every case",
    "device_silent": "",  # the place never comes clear
    "reading_out_of_range": "",  # the camera reports a part outside x_range_mm
}
SCENARIO_OF = {
    "start_away": "start_away",
    "start_mid_cycle": "start_mid_cycle",
    "gripper_silent": "gripper_silent",
    "gripper_stuck": "gripper_stuck",
    "gripper_sealed": "gripper_sealed",  # the kind's own: the cup seals on the part as the program gives up the grip
    "part_out_of_range": "reading_out_of_range",
    "place_blocked": "device_silent",
    "belt_stands": "belt_stands",  # the kind's own: the belt stands while a part is on its way
    "stop_while_standing": "stop_while_standing",  # the kind's own: the line's cycle stop while the belt stands
    "no_part": "no_part",  # the kind's own: no part comes for longer than no_part_s
}
# each sleep of the program ends this much later than it asks (a pass of a polling loop: its statements and the
# controller's interpreter cycle; assumed, no manual here states it): a program that times the belt by its passes
# counted as exact sleeps measures its speed wrong
SLEEP_OVERHEAD_S = 0.002
# the stray_pulses case: a stray pulse of the camera's trigger (UR's trigger input, ABB's sync input) at this moment
# (after the program has emptied the unit's queue at its start), the part at least STRAY_AHEAD_MM behind it (1.5
# times the Sync Separation), and a double pulse DOUBLE_S after the part's own
STRAY_AT_S = 4.0
STRAY_AHEAD_MM = 60.0
DOUBLE_S = 0.02
# the tall_then_low case: the tall part this far before the intercept point when the program first reads the queue (an
# intercept arrives after it), the low one at least TALL_GAP_MM behind it
TALL_AHEAD_MM = 40.0
TALL_GAP_MM = 100.0
RISE_WOBBLE = 0.2  # the speeding_up case: the speed swings by this share of its mean
QUEUED_S = 2.0  # the rollover_queued case: its parts this far apart (s)
SEEN_BEFORE_S = 1.0  # the seen_before_start case: the camera saw the part this long before the program started
OUT_OF_STEP_CASES = frozenset({"unit_missed_sync", "stray_pulses"})
# the robot's own latch against the PLC's queue (a target that latches its encoder at the camera's trigger): its decoder
# counting half the ticks the cell states for it (calibrated at another scale), a trigger pulse its input missed
MISMATCH_CASES = {"latch_scale": "the wait above the window", "trigger_missed": "before the arm moves"}
OVERRUN_GAP_MM = 150.0  # the latch_overrun case: the second part this far behind the first
CHATTER, CHATTER_S = LATCH_RING + 8, 0.02  # the latch_overrun case: pulses after the part's own, this far apart (s)
STAND_EXTRA_S = 2.0  # the belt_stands case: the belt stands this much longer than belt_stop_s
RUN_ON_S = 10.0  # the belt_stands case: its cycle stop this long after the part could have left the window
HALTED_S = 3600.0  # the stop_while_standing case: the belt stands this long (longer than any run)
# the no_part case: the line's cycle stop comes this long after no_part_s (a wait that counts its reads says so a little
# late: each read's pass takes SLEEP_OVERHEAD_S more than its sleep, a sixth more at 12 ms)
NO_PART_EXTRA_S = 10.0


@dataclass(frozen=True)
class BeltCase:
    """A run: the belt (speed, wobble, where the counter starts), the parts the camera sees, how the gripper
    answers, where the arm starts and whether it holds a part then, whether the place comes clear, how old the
    counter's count is when the program reads it and how long the gripper takes to hold a part."""

    category: str
    belt: Belt
    parts: tuple[Part, ...]
    robot_zero: int = 0  # the controller's own encoder against the PLC's counter
    robot_scale: float = 1.0  # the controller's own encoder against the scale the cell states for it (1: as stated)
    unlatched: frozenset = frozenset()  # the parts whose trigger pulse the controller's own input missed (numbers)
    gripper: str = "prompt"
    start: str = "home"
    held: bool = False
    place: str = "clear"
    latency_s: float = 0.0  # the count's age at least (PLC and fieldbus, the arm's start)
    age_cycle_s: float = 0.0  # the PLC's cycle: the count's age grows by up to this between its copies
    age_phase_s: float = 0.0
    grip_s: float = 0.0
    stop_s: float = 0.0  # the line's cycle stop not before this (s)
    pulses: tuple = ()  # trigger pulses no part made (a double pulse, a part the PLC dropped): moments (s)
    before: tuple = ()  # parts a stopped run took from the PLC before this start (their objects still queued)
    # the mechanical unit's own sync input against the PLC's queue (ABB native; the trigger's pulses above are syncs to
    # it too): the parts whose sync it missed (numbers)
    unit_missed: frozenset = frozenset()

    @property
    def scenario(self) -> str:
        return SCENARIO_OF.get(self.category, "nominal")


def cases(cell, seed: int = 0) -> list[BeltCase]:
    """Belts at a constant and a varying speed, the counter starting just below its wrap (it rolls over
    during the picks), parts at random places across the belt and random gaps, and a part that comes
    right behind another (it has left the window before the arm is free: skipped); the latencies an
    intercept budgets for, each at random within the cell's bounds."""
    rng = random.Random(seed)
    conveyor, pick = conveyor_of(cell), conveyor_of(cell).pick
    e = conveyor.counts_per_mm
    span = 2**COUNTER_BITS
    # the counter wraps about 3,000 counts after the camera saw the first part (0.5 s, at 80 mm/s): between
    # the count it reports and the counts the program reads while the part travels to the window
    ahead = 3000 + abs(e) * 80.0 * 0.5
    near_wrap = round(span - ahead) if e > 0 else round(ahead)

    def timing() -> dict:
        # the count's age runs through count_latency_s as the PLC copies the counter once a cycle (the cycle the
        # interval's width, the copies at a random phase); the arm's start (motion_start_s) adds a constant
        low, high = pick.count_latency_s
        age = rng.uniform(low, high)  # at the run's start
        latency = low + rng.uniform(*pick.motion_start_s)
        return {
            "latency_s": latency,
            "age_cycle_s": high - low,
            "age_phase_s": low - age,
            "grip_s": rng.uniform(*pick.grip_s),
        }

    out = []
    for category, speed, wobble, start in (
        ("constant_speed", 60.0, 0.0, rng.randrange(span)),
        ("varying_speed", 60.0, 0.4, rng.randrange(span)),
        ("rollover", 80.0, 0.0, near_wrap),
    ):
        speed = min(speed, pick.belt_speed_max_mm_s / (1.0 + wobble))  # never faster than the cell says
        # a varying belt never changes its speed faster than the cell's belt_accel_mm_s2 (where it states one)
        accel = pick.belt_accel_mm_s2
        period = 5.0 if wobble == 0 or accel == 0 else max(5.0, 2 * math.pi * speed * wobble / accel)
        belt = Belt(speed, e, COUNTER_BITS, start, wobble, period_s=period)
        parts, t = [], 0.5
        for seq in range(1, 5):
            parts.append(_random_part(rng, pick, seq, t))
            t += rng.uniform(9.0, 14.0)
        zero = rng.randrange(-(2**30), 2**30)
        if category == "rollover":  # the controller's own encoder on the same wrap (UR's filtered count)
            zero = 0
        out.append(BeltCase(category, belt, tuple(parts), zero, **timing()))
    belt = Belt(min(70.0, pick.belt_speed_max_mm_s), e, COUNTER_BITS, rng.randrange(span))
    # parts 2 and 3 come right behind part 1: while the arm works on it they travel on (part 2 too late for
    # an intercept or past the window's end, part 3 past the end when the program takes it); part 4 later
    late = tuple(_random_part(rng, pick, seq, seen) for seq, seen in ((1, 0.5), (2, 1.0), (3, 1.5), (4, 20.0)))
    out.append(BeltCase("part_too_late", belt, late, rng.randrange(-(2**30), 2**30), **timing()))
    # the belt at its fastest (the cell's belt_speed_max_mm_s): parts 1.5 and 2.5 s apart reach the window's end
    # while the arm still works (on the bundled cell part 3 is read some 65 mm past it: a program that skips only
    # well past the end picks it, and fails)
    fast = Belt(pick.belt_speed_max_mm_s, e, COUNTER_BITS, rng.randrange(span))
    quick = tuple(_random_part(rng, pick, seq, seen) for seq, seen in ((1, 0.5), (2, 2.0), (3, 4.5), (4, 12.0)))
    out.append(BeltCase("fast_belt", fast, quick, rng.randrange(-(2**30), 2**30), **timing()))
    first = out[0]
    one = replace(first, parts=first.parts[:1])
    # a part the camera saw while the line stood still before the program started: when the program reads it, it
    # is PAST_END_MM beyond the window's end (the program must skip it, not chase it)
    slow = replace(first.belt, wobble=0.0)
    seen = -(pick.window_mm[1] + PAST_END_MM + conveyor.camera_offset_mm) / slow.speed_mm_s + DECISION_S
    out.append(replace(one, category="part_past_the_window", belt=slow, parts=(replace(one.parts[0], seen_s=seen),)))
    if pick.min_gap_mm > 0:  # a part half the minimum distance behind another on a slow belt: both reach the window
        crawl = replace(slow, speed_mm_s=min(20.0, pick.belt_speed_max_mm_s))
        lead = one.parts[0]
        close = _random_part(rng, pick, 2, lead.seen_s + 0.5 * pick.min_gap_mm / crawl.speed_mm_s)
        out.append(replace(one, category="part_too_close", belt=crawl, parts=(lead, close)))
    (x0, x1), _ = pick.x_range_mm, pick.z_range_mm
    wrong = replace(one.parts[0], x=x1 + 0.5 * (x1 - x0))
    scenarios = [
        replace(one, category="start_away", start="away"),
        replace(one, category="start_mid_cycle", start="mid_cycle", held=True),
        replace(one, category="gripper_silent", gripper="silent"),
        replace(one, category="gripper_stuck", gripper="stuck"),
        # the cup seals on the part only as the program gives up (its feedback on from the release until the vacuum
        # has decayed, the case's grip_s later): a program that lifts before the feedback drops carries the part up
        replace(one, category="gripper_sealed", gripper="sealed"),
        replace(one, category="part_out_of_range", parts=(wrong,)),
    ]
    if pick.place_clear:
        scenarios.append(replace(one, category="place_blocked", place="blocked"))
    # the belt stands (then runs again at once) while the part is halfway from the camera's line to the window: the
    # arm waits above the belt and must stay there; and a line with no part for longer than no_part_s
    halfway = slow.time_at(0.5 * (conveyor.camera_offset_mm + pick.window_mm[0])) + one.parts[0].seen_s
    stands = replace(slow, stops=((halfway, pick.belt_stop_s + STAND_EXTRA_S),))
    # the line's cycle stop only once the part has had time to reach the window's end on the belt that stood (and
    # RUN_ON_S more: a later stand of a case made from this one): a stop while the belt stands ends the cycle there
    seen = one.parts[0].seen_s
    gone = stands.time_at(stands.travel_mm(seen) + conveyor.camera_offset_mm + pick.window_mm[1])
    scenarios.append(replace(one, category="belt_stands", belt=stands, stop_s=gone + RUN_ON_S))
    # the belt stands for good with the part on its way and the line's cycle stop comes once it has stood belt_stop_s
    # and more: the arm waits above the belt, and the program must end its cycle there (not wait for ever)
    halted = replace(slow, stops=((halfway, HALTED_S),))
    stop_at = halfway + pick.belt_stop_s + STAND_EXTRA_S
    scenarios.append(replace(one, category="stop_while_standing", belt=halted, stop_s=stop_at))
    scenarios.append(replace(one, category="no_part", parts=(), stop_s=pick.no_part_s + NO_PART_EXTRA_S))
    if pick.unit:  # the unit's queue out of step with the PLC's: a sync it missed
        scenarios.append(replace(one, category="unit_missed_sync", belt=slow, unit_missed=frozenset({1})))
    # a stray trigger pulse ahead of the part and a double pulse right after its own: UR's latch passes the stray's
    # count over and takes the first of the double; ABB's unit queues the stray as an object (out of step: a stop)
    ahead = max(1.5 * pick.min_gap_mm, STRAY_AHEAD_MM)
    part = replace(one.parts[0], seen_s=STRAY_AT_S + ahead / slow.speed_mm_s)
    pulses = (STRAY_AT_S, part.seen_s + DOUBLE_S)
    scenarios.append(replace(one, category="stray_pulses", belt=slow, parts=(part,), pulses=pulses))
    # a part the camera saw SEEN_BEFORE_S before the program started, still upstream of the window when read: UR has
    # no latch of it and a native unit's queue was emptied at the start (both skip it with a message); the PLC's own
    # queue picks it
    early = replace(one.parts[0], seen_s=-SEEN_BEFORE_S)
    scenarios.append(replace(one, category="seen_before_start", belt=slow, parts=(early,)))
    if pick.trigger_input:  # the robot's own count and the PLC's disagree: a stop with its message, no grip
        scenarios.append(replace(one, category="latch_scale", belt=slow, robot_scale=0.5))
        scenarios.append(replace(one, category="trigger_missed", belt=slow, unlatched=frozenset({1})))
        # a trigger that chatters right after a second part's pulse while the arm works on the first: more pulses
        # pending than the robot's latch ring holds (CHATTER of them, CHATTER_S apart) when the program takes the second
        # part, its own count overwritten: a stop with its message then
        lead = one.parts[0]
        second = replace(_random_part(rng, pick, 2, 0.0), seen_s=lead.seen_s + OVERRUN_GAP_MM / slow.speed_mm_s)
        chatter = tuple(second.seen_s + CHATTER_S * (k + 1) for k in range(CHATTER))
        scenarios.append(replace(one, category="latch_overrun", belt=slow, parts=(lead, second), pulses=chatter))
    # the counter's wrap with parts queued: on the rollover belt four parts QUEUED_S apart, the later ones seen before
    # the counter wraps and taken after it (the arm busy with the first): each picked or given up for a reason verify
    # takes
    rollover = next(c for c in out if c.category == "rollover")
    queued = tuple(_random_part(rng, pick, seq, 0.5 + QUEUED_S * (seq - 1)) for seq in range(1, 5))
    out.append(replace(rollover, category="rollover_queued", parts=queued))
    # a tall part the arm cannot take (an intercept reaches it too late) and a low one the least spacing behind it (at
    # least TALL_GAP_MM), both across from each other at the belt's fastest: the part left on the belt may still lie
    # under the gripper when it comes down for the low one
    gap = max(pick.min_gap_mm, TALL_GAP_MM)
    rush = replace(slow, speed_mm_s=pick.belt_speed_max_mm_s)
    (z0, z1), x = pick.z_range_mm, 0.5 * sum(pick.x_range_mm)
    seen = DECISION_S - (pick.intercept_mm - TALL_AHEAD_MM + conveyor.camera_offset_mm) / rush.speed_mm_s
    tall = Part(1, seen, x, z1 - 0.05 * (z1 - z0))
    low = Part(2, seen + gap / rush.speed_mm_s, x, z0 + 0.05 * (z1 - z0))
    out.append(replace(one, category="tall_then_low", belt=rush, parts=(tall, low)))
    # the belt speeding up at the cell's belt_accel_mm_s2, its fastest change, while an intercepting arm comes down onto
    # the part (the middle of the lead at the steepest rise of a swinging speed, never above belt_speed_max_mm_s): what
    # the speed measured before the descent does not know
    if pick.belt_accel_mm_s2 > 0 and "intercept" in pick.tracking.values():
        rise = _speeding_up(cell, rng, conveyor, pick, first)
        if rise is not None:
            out.append(rise)
    short = [c for c in out if len(c.parts) < 4] + [c for c in out if c.category == "part_too_late"]
    rest = [c for c in out if c not in short]
    return scenarios + short + rest  # the short runs first: a run that stops at its first mismatch ends early


def _speeding_up(cell, rng, conveyor, pick, first: BeltCase) -> BeltCase | None:
    """One part on a belt whose speed swings by RISE_WOBBLE, its steepest rise (belt_accel_mm_s2) in the middle of the
    intercept's lead as the part reaches the intercept point."""
    from codegen.controllers import get_target
    from codegen.kinds.conveyor.timing import lead_seconds

    intercepts = [t for t, mode in pick.tracking.items() if mode == "intercept"]
    lead = lead_seconds(cell, get_target(intercepts[0]))
    speed = pick.belt_speed_max_mm_s / (1.0 + RISE_WOBBLE)
    period = 2 * math.pi * speed * RISE_WOBBLE / pick.belt_accel_mm_s2
    belt = Belt(speed, conveyor.counts_per_mm, COUNTER_BITS, rng.randrange(2**COUNTER_BITS), RISE_WOBBLE, period)
    distance = conveyor.camera_offset_mm + pick.intercept_mm
    k = math.ceil((distance / (speed * (1.0 - RISE_WOBBLE)) + DECISION_S + lead) / period)
    arrive = k * period + 0.5 * lead  # the speed rises fastest at whole periods of its running time
    seen = belt.time_at(belt.travel_mm(arrive) - distance)
    part = replace(_random_part(rng, pick, 1, 0.0), seen_s=seen)
    return replace(first, category="speeding_up", belt=belt, parts=(part,))


def _random_part(rng, pick, seq: int, seen_s: float) -> Part:
    (x0, x1), (z0, z1) = pick.x_range_mm, pick.z_range_mm
    return Part(seq, seen_s, rng.uniform(x0, x1), rng.uniform(z0, z1))
