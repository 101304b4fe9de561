"""Verify pick-from-belt programs: each case run against a simulated belt; the parts judged where they really are,
every move against the pick plan, the common scenarios (the arm away, the gripper silent, a bad reading)."""

from __future__ import annotations

from dataclasses import dataclass, replace

from codegen import protocol
from codegen.controllers import get_target
from codegen.emit import Emitter
from codegen.guard import NOT_RELEASED, halt_message
from codegen.kinds.conveyor import native, plan
from codegen.kinds.conveyor.cases import MISMATCH_CASES, OUT_OF_STEP_CASES, SCENARIOS, SLEEP_OVERHEAD_S, BeltCase, cases
from codegen.kinds.conveyor.judge import SKIPS, belt_zone, left_low, struck
from codegen.kinds.conveyor.judge import judge as judge_parts
from codegen.kinds.conveyor.judge import not_held as judge_not_held
from codegen.kinds.conveyor.kind import KIND
from codegen.kinds.conveyor.program import (
    BAD_READING,
    MISMATCH,
    OUT_OF_STEP,
    OVERRUN,
    STANDS,
    STOPPED,
    no_part,
    place_blocked,
)
from codegen.kinds.conveyor.section import conveyor_of
from codegen.kinds.conveyor.start import first_moves, grip_pose, start_joints
from codegen.model.io import signal_name
from codegen.sim.belt import BeltLine, TrackingUnit
from codegen.sim.bus import bus_for
from codegen.sim.gripper import Gripper, SealedCup
from codegen.verify.plan import Expectation, Judgement, PlannedOutput, Setup, tool_inputs

# a run's statements: the bundled cell's longest case takes about 90,000 (an intercept polls the encoder every 12 ms); a
# program that waits for a part it has lost (a counter read wrongly) stops here (about twice that), not after
# minutes; a program whose thread latches the camera's trigger runs a few statements every controller frame: three
# times as many (UR's longest case about 250,000)
STEP_LIMIT = 200_000
THREAD_STEPS = 3


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
        # the controller's own decoder at the scale the cell states for it (ticks_per_mm), against the PLC's counter
        robot_scale=case.robot_scale * conveyor_of(cell).robot_ticks_per_mm / conveyor_of(cell).counts_per_mm,
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
    if case.category == "stop_while_standing":
        return _stopped_waiting(cell, target_name, case, trace, first, start_outputs, names)
    # more trigger pulses pending than the latch ring holds when the second part is taken (the first picked meanwhile):
    # a stop with its message then, the first part judged as any
    overrun = case.category == "latch_overrun" and target_name in conveyor_of(cell).pick.trigger_input
    judged = replace(case, parts=case.parts[:1]) if overrun else case
    stop = OVERRUN if overrun else None
    problem, pos, rot = judge_parts(cell, target_name, judged, trace, line, output, stop)
    problem = problem or left_low(cell, target_name, judged, trace, len(first), closes)
    problem = problem or struck(cell, target_name, judged, trace)
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
    halt = emitter.string(OVERRUN) if overrun else None
    expected = Expectation(halt, tuple(first) + tuple(moves), outputs, output_names=names)
    return Judgement([expected], figures=(len(judged.parts) - skipped, skipped), errors=([pos], [rot]))


def _stopped_waiting(cell, target_name: str, case, trace, first, start_outputs, names) -> Judgement:
    """The line's cycle stop while the arm waits above a standing belt with the part on its way: the arm's moves for a
    part given up (to where it waits; an intercept's descent to the approach height and back), no grip, the belt
    zone's output off, the program's end said after the stop came (a program that waits for the belt for ever runs into
    the step limit instead)."""
    target = get_target(target_name)
    mode = conveyor_of(cell).pick.tracking[target_name]
    ended = [t for m, t in zip(trace.messages, trace.message_times, strict=True) if m == STOPPED]
    if not ended or ended[-1] < case.stop_s - 1e-9:
        return Judgement([], problem=f"the line's cycle stop at {case.stop_s:.3f} s, the program's end said at {ended}")
    problem = belt_zone(cell, target_name, trace)
    if problem is not None:
        return Judgement([], problem=problem)
    # the move to where the arm waits; an intercepting arm stopped in its second stage also went down to the part's
    # approach height and back up to the clear height (a part given up)
    moves = plan._given_up(cell, target, mode, trace.moves[len(first) :], len(first))
    if isinstance(moves, str):
        return Judgement([], problem=moves)
    return Judgement([Expectation(None, (*first, *moves), start_outputs, output_names=names)])


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
            if case.category == "stop_while_standing" and move.start_time >= case.stop_s - 1e-9:
                continue  # the way up off the belt once the line's cycle stop has come
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
