"""Verify pick-from-belt programs: each case run against a simulated belt; the parts judged where they really are,
every move against the pick plan, the common scenarios (the arm away, the gripper silent, a bad reading)."""

from __future__ import annotations

import math
import random
from dataclasses import dataclass, replace

from codegen import protocol
from codegen.controllers import get_target
from codegen.emit import Emitter
from codegen.guard import NOT_RELEASED, halt_message
from codegen.kinds.conveyor import native, plan
from codegen.kinds.conveyor.judge import SKIPS, belt_zone, left_low, struck
from codegen.kinds.conveyor.judge import judge as judge_parts
from codegen.kinds.conveyor.judge import not_held as judge_not_held
from codegen.kinds.conveyor.kind import KIND
from codegen.kinds.conveyor.program import BAD_READING, MISMATCH, OUT_OF_STEP, STANDS, no_part, place_blocked
from codegen.kinds.conveyor.section import conveyor_of
from codegen.kinds.conveyor.start import first_moves, grip_pose, start_joints
from codegen.model.io import signal_name
from codegen.sim.belt import Belt, BeltLine, Part, TrackingUnit
from codegen.sim.bus import bus_for
from codegen.sim.gripper import Gripper, SealedCup
from codegen.verify.plan import Expectation, Judgement, PlannedOutput, Setup, tool_inputs

# a run's statements: the bundled cell's longest case takes about 90,000 (an intercept polls the encoder every 12 ms); a
# program that waits for a part it has lost (a counter read wrongly) stops here (about twice that), not after
# minutes; a program whose thread latches the camera's trigger runs a few statements every controller frame: three
# times as many (UR's longest case about 250,000)
STEP_LIMIT = 200_000
THREAD_STEPS = 3
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
QUEUED_S = 2.0  # the rollover_queued case: its parts this far apart (s)
SEEN_BEFORE_S = 1.0  # the seen_before_start case: the camera saw the part this long before the program started
OUT_OF_STEP_CASES = frozenset({"unit_missed_sync", "stray_pulses"})
# the robot's own latch against the PLC's queue (a target that latches its encoder at the camera's trigger): its decoder
# counting half the PLC's counts (the belt calibrated with the PLC's), a trigger pulse its input missed
MISMATCH_CASES = {"latch_scale": "the wait above the window", "trigger_missed": "before the arm moves"}
STAND_EXTRA_S = 2.0  # the belt_stands case: the belt stands this much longer than belt_stop_s
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
    robot_scale: float = 1.0  # the controller's own encoder's counts per count of the PLC's counter
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
    scenarios.append(replace(one, category="belt_stands", belt=stands))
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
    short = [c for c in out if len(c.parts) < 4] + [c for c in out if c.category == "part_too_late"]
    rest = [c for c in out if c not in short]
    return scenarios + short + rest  # the short runs first: a run that stops at its first mismatch ends early


def _random_part(rng, pick, seq: int, seen_s: float) -> Part:
    (x0, x1), (z0, z1) = pick.x_range_mm, pick.z_range_mm
    return Part(seq, seen_s, rng.uniform(x0, x1), rng.uniform(z0, z1))


def setup(cell, target_name: str, case: BeltCase) -> Setup:
    target = get_target(target_name)
    pick = conveyor_of(cell).pick
    wiring = pick.encoder_inputs.get(target_name)  # the installation: A and B as the cell says
    unit = None
    if target_name in pick.unit:  # the belt as the controller's mechanical unit (its tracking option)
        unit = TrackingUnit(
            native.settings(cell, target),
            case.belt,
            [*case.before, *case.parts],
            extra_syncs=case.pulses,
            missed=case.unit_missed,
        )
    line = BeltLine(
        case.belt,
        list(case.parts),
        bus_for(target, KIND.facts(target)),
        robot_zero=case.robot_zero,
        robot_scale=case.robot_scale,
        unlatched=case.unlatched,
        wiring=None if not wiring else tuple(wiring),
        unit=unit,
        latency_s=case.latency_s,
        age_cycle_s=case.age_cycle_s,
        age_phase_s=case.age_phase_s,
        stop_s=case.stop_s,
        sleep_overhead_s=SLEEP_OVERHEAD_S,
        pulses=case.pulses,
        trigger=signal_name(target, "input", pick.trigger_input[target_name])
        if target_name in pick.trigger_input
        else None,
    )
    output = signal_name(target, "output", cell.io.output[target_name])
    feedback = signal_name(target, "input", cell.io.feedback[target_name])
    # a gripper that answers as the cell's does: its hold and its release grip_s after the output (a prompt one)
    late = case.gripper == "prompt" and case.grip_s > 0.0
    if case.gripper == "sealed":
        gripper = SealedCup(output, feedback, cell.io.value, late_s=case.grip_s)
    else:
        gripper = Gripper(output, feedback, cell.io.value, "late" if late else case.gripper, late_s=case.grip_s)
    signals = {feedback: case.held}
    if case.held:  # closed on a part since the stopped cycle
        signals[output] = cell.io.value
    if target_name in pick.place_clear:
        signals[signal_name(target, "input", pick.place_clear[target_name])] = case.place == "clear"
    joints = start_joints(cell, target_name, case.start)
    limit = STEP_LIMIT * (THREAD_STEPS if target_name in pick.trigger_input else 1)
    return Setup(tool_inputs(cell, target_name), (line, gripper), signals, joints, step_limit=limit)


def judge(cell, target_name: str, case: BeltCase, trace, setup: Setup) -> Judgement:
    """Where the program stops (the gripper's silences, a bad reading, a place never clear), else every part
    judged where it really is (codegen/kinds/conveyor/judge.py) and every move against the pick plan, after the
    start the case demands (the way home from away, a part held put down)."""
    target = get_target(target_name)
    line = setup.devices[0]
    emitter = Emitter(target)
    output = signal_name(target, "output", cell.io.output[target_name])
    mode = conveyor_of(cell).pick.tracking[target_name]
    first, release_at = first_moves(cell, target, case.start, case.held)
    events = [o for o in trace.outputs if o.name == output]
    closes = [o for o in events if o.value == cell.io.value]
    # a part held at the start: the grip asserted again before any motion (the way home would drop it)
    held_at = None if not case.held or release_at is None else 0
    closes = closes[1:] if held_at is not None else closes
    opens = [o for o in events if o.value != cell.io.value][1:]  # after the one at the start
    names = frozenset({output})
    start_outputs = plan.outputs(cell, output, [], [], release_at, held_at)
    if case.category == "part_out_of_range":  # the camera's reading is refused before the arm moves for it
        return Judgement([Expectation(emitter.string(BAD_READING), tuple(first), start_outputs, output_names=names)])
    stops = {
        "gripper_stuck": (halt_message(cell, NOT_RELEASED, None, 0), plan.RELEASE[mode]),
        "place_blocked": (place_blocked(cell), plan.RELEASE[mode] - 1),
    }
    if case.gripper in ("silent", "sealed"):  # every target: the part left on the belt, no stop there
        return _not_held(cell, target_name, case, trace, first, start_outputs, output, names, setup.devices[1])
    if case.category in stops:  # the first part's moves up to the stop: the grip, the release, above the place
        message, count = stops[case.category]
        moves = [plan.planned(segment, cell, target, mode) for segment in plan.PICK[mode][:count]]
        outputs = [*start_outputs, PlannedOutput(output, cell.io.value, len(first) + plan.GRIP[mode], "on the part")]
        if case.category == "gripper_stuck":
            at = len(first) + plan.RELEASE[mode]
            outputs.append(PlannedOutput(output, not cell.io.value, at, "at the place"))
        expected = Expectation(emitter.string(message), (*first, *moves), tuple(outputs), output_names=names)
        return Judgement([expected])
    if case.category in OUT_OF_STEP_CASES and target_name in conveyor_of(cell).pick.unit:
        # the unit's queue out of step: the arm waits above the window's start, across from the part, and the program
        # stops with its message (no grip) once the part is in the window by the PLC's count
        pick = conveyor_of(cell).pick
        wait = grip_pose(cell, case.parts[0].x, pick.window_mm[0], pick.z_range_mm[1] + pick.approach_dz)
        moves = (*first, plan.planned(plan.PICK[mode][0], cell, target, mode, pose=wait))
        return Judgement([Expectation(emitter.string(OUT_OF_STEP), moves, start_outputs, output_names=names)])
    if case.category in MISMATCH_CASES and target_name in conveyor_of(cell).pick.trigger_input:
        # the robot's own count and the PLC's disagree: a stop with its message, once the part reaches the window (the
        # arm above the window's start, across from it) or, a part without a latch of its own, before the arm moves
        pick = conveyor_of(cell).pick
        wait = grip_pose(cell, case.parts[0].x, pick.window_mm[0], pick.z_range_mm[1] + pick.approach_dz)
        moves = tuple(first)
        if case.category == "latch_scale":
            moves = (*first, plan.planned(plan.PICK[mode][0], cell, target, mode, pose=wait))
        return Judgement([Expectation(emitter.string(MISMATCH), moves, start_outputs, output_names=names)])
    problem = waits(cell, case, trace)
    if problem is not None:
        return Judgement([], problem=problem)
    problem, pos, rot = judge_parts(cell, target_name, case, trace, line, output)
    problem = problem or left_low(cell, target_name, case, trace, len(first), closes)
    problem = problem or struck(cell, target_name, case, trace)
    if problem is not None:
        return Judgement([], problem=problem)
    moves = plan.lay_over(cell, target, mode, len(first), trace.moves, closes, opens)
    if isinstance(moves, str):
        return Judgement([], problem=moves)
    zone = belt_zone(cell, target_name, trace)  # the belt zone's output over the moves low on the belt, once they fit
    problem = zone or lifted_early(cell, trace, closes, setup.devices[1])
    problem = problem or released_early(trace, opens, setup.devices[1], case.held)
    if problem is not None:
        return Judgement([], problem=problem)
    skipped = sum(1 for m in trace.messages if m.startswith(SKIPS))
    outputs = start_outputs + plan.outputs(cell, output, closes, opens, None)
    expected = Expectation(None, tuple(first) + tuple(moves), outputs, output_names=names)
    return Judgement([expected], figures=(len(case.parts) - skipped, skipped), errors=([pos], [rot]))


def lifted_early(cell, trace, closes: list, gripper: Gripper) -> str | None:
    """Each grip's next move (the lift) sets off only once the gripper holds the part (its feedback on after the
    output, as the simulated gripper answers: grip_s later): a program that lifts on a fixed time instead leaves the
    part on the belt."""
    for number, close in enumerate(closes, start=1):
        held = next((t for t, on in gripper.changes if on and t >= close.time - 1e-9), None)
        if close.after_moves >= len(trace.moves):
            continue
        lift = trace.moves[close.after_moves]
        if held is None or lift.start_time < held - 1e-6:
            when = "never" if held is None else f"at {held:.3f} s"
            return f"grip {number}: the arm set off at {lift.start_time:.3f} s, the gripper held the part {when}"
    return None


def released_early(trace, opens: list, gripper: Gripper, held: bool) -> str | None:
    """Each release's next move (the lift from the place, or off a part the grip failed on) sets off only once the
    gripper has let go of the part (its feedback off after the output, as the simulated gripper answers: grip_s later;
    at once where it never read on): a program that lifts on the output alone carries the part, still held by the
    vacuum, up. held: the feedback at the start."""
    for number, open_ in enumerate(opens, start=1):
        if open_.after_moves >= len(trace.moves):
            continue
        let_go = gripper.let_go(open_.time, held)
        lift = trace.moves[open_.after_moves]
        if let_go is None or lift.start_time < let_go - 1e-6:
            when = "never" if let_go is None else f"at {let_go:.3f} s"
            return f"release {number}: the arm set off at {lift.start_time:.3f} s, the gripper let go {when}"
    return None


def _not_held(cell, target_name: str, case, trace, first, start_outputs, output, names, gripper) -> Judgement:
    """A grip never confirmed while the arm is on the part (every target): released at once, up off the part by
    approach_dz (a tracking arm still following it), the part skipped with a message, the program on to the line's
    stop (judge.not_held: where the part really is); the moves as a part given up (plan.GIVEN_UP: the descent and
    its lift, then where the program leaves the belt), without the payload."""
    target = get_target(target_name)
    mode = conveyor_of(cell).pick.tracking[target_name]
    problem, pos, rot = judge_not_held(cell, target_name, case, trace, output, len(first))
    if problem is not None:
        return Judgement([], problem=problem)
    moves = plan._given_up(cell, target, mode, trace.moves[len(first) :], len(first))
    if isinstance(moves, str):
        return Judgement([], problem=moves)
    opens = [o for o in trace.outputs if o.name == output and o.value != cell.io.value][1:]
    problem = belt_zone(cell, target_name, trace) or released_early(trace, opens, gripper, case.held)
    if problem is not None:
        return Judgement([], problem=problem)
    at = len(first) + plan.GRIP[mode]
    outputs = (
        *start_outputs,
        PlannedOutput(output, cell.io.value, at, "on the part"),
        PlannedOutput(output, not cell.io.value, at, "released on the belt"),
    )
    expected = Expectation(None, (*first, *moves), outputs, output_names=names)
    return Judgement([expected], figures=(0, 1), errors=([pos], [rot]))


def waits(cell, case: BeltCase, trace) -> str | None:
    """The waits' messages: no part for no_part_s said once, and only when the wait for a part lasted that long;
    while the belt stands with a part on its way, no move (the arm stays above the belt) and, once it has stood
    belt_stop_s, the belt's standing said once for that part (while it stands; never while it runs)."""
    pick = conveyor_of(cell).pick
    said = [t for m, t in zip(trace.messages, trace.message_times, strict=True) if m == no_part(cell)]
    moments = sorted([0.0, *(p.seen_s for p in case.parts)])
    longest = max(b - a for a, b in zip(moments, [*moments[1:], max(case.stop_s, moments[-1])], strict=True))
    if len(said) > 1 or (said and said[0] < pick.no_part_s) or (said and longest < pick.no_part_s):
        return f"'no part' said at {said} s; the longest wait for a part {longest:g} s (no_part_s {pick.no_part_s:g})"
    if case.category == "no_part" and not said:
        return f"no part came for {case.stop_s:g} s, and the program did not say so (no_part_s {pick.no_part_s:g})"
    stands = [(m, t) for m, t in zip(trace.messages, trace.message_times, strict=True) if m.startswith(STANDS)]
    for start, length in case.belt.stops:
        for move in trace.moves:
            if move.start_time < start + length and move.end_time > start:
                return (
                    f"a move (line {move.line}) from {move.start_time:.3f} s to {move.end_time:.3f} s while the belt "
                    f"stood ({start:.3f} s to {start + length:.3f} s)"
                )
        inside = [(m, t) for m, t in stands if start + pick.belt_stop_s - 1e-9 <= t <= start + length]
        if length > pick.belt_stop_s + 1.0 and len(inside) != 1:
            return f"the belt stood {length:g} s from {start:.3f} s: said {len(inside)} times in it ({stands})"
    for _m, t in stands:
        if not any(start + pick.belt_stop_s - 1e-9 <= t <= start + length for start, length in case.belt.stops):
            return f"the belt's standing said at {t:.3f} s, when it had not stood {pick.belt_stop_s:g} s"
    return None


@dataclass
class BeltFigures(protocol.Figures):
    picked: int = 0
    skipped: int = 0

    def count(self, case, judged: tuple[int, int]) -> None:
        self.picked += judged[0]
        self.skipped += judged[1]

    def as_json(self) -> dict:
        return {"parts_picked": self.picked, "parts_skipped": self.skipped}


class VerifyPart(protocol.VerifyPlan):
    """The belt's parts (each judged against the belt's log of where it was), their interruptions and the queue."""

    report_key = "conveyors"
    scenarios = SCENARIOS
    figures = BeltFigures
    listed = {  # a row as `codegen verify --json` lists it under "conveyors"
        "target": "target",
        "files": "files",
        "cases": "cases",
        "mismatches": "mismatches",
        "parts_picked": "parts_picked",
        "parts_skipped": "parts_skipped",
        "pos_max_mm": "position_error_mm.max",
        "rot_max_deg": "orientation_error_deg.max",
        "first_mismatches": "first_mismatches",
    }

    def cases(self, cell, source, count: int, seed: int) -> list:
        return cases(cell, seed)

    def setup(self, cell, source, case):
        return setup(cell, source.target, case)

    def judge(self, cell, source, case, trace, setup):
        return judge(cell, source.target, case, trace, setup)

    def report_lines(self, rows: list) -> list[str]:
        lines = ["conveyor  target    cases  fail  picked  skipped"]
        for r in rows:
            figures = r.figures or BeltFigures()
            counts = f"{r.cases:6d} {r.mismatches:5d} {figures.picked:7d} {figures.skipped:8d}"
            lines.append(f"{'belt':9} {r.target:8} {counts}")
        return lines
