"""Verify pick-from-belt programs: each case run against a simulated belt; the parts judged where they really are,
every move against the pick plan, the common scenarios (the arm away, the gripper silent, a bad reading)."""

from __future__ import annotations

import random
from dataclasses import dataclass, replace

import numpy as np

from codegen.controllers import get_target
from codegen.emit import Emitter
from codegen.guard import NO_FEEDBACK, NOT_RELEASED, halt_message
from codegen.kinds.conveyor import plan
from codegen.kinds.conveyor.facts import facts
from codegen.kinds.conveyor.judge import judge as judge_parts
from codegen.kinds.conveyor.program import BAD_READING, SKIPPED, TOO_LATE
from codegen.kinds.conveyor.section import conveyor_of
from codegen.model.io import signal_name
from codegen.reference import home_move
from codegen.robot import solve
from codegen.sim.belt import Belt, BeltLine, Part
from codegen.sim.bus import bus_for
from codegen.sim.gripper import Gripper
from codegen.verify.plan import START_AWAY_DEG, Expectation, Judgement, PlannedMove, PlannedOutput, Setup, refuses_start

# a run's statements: the bundled cell's longest case takes 86,000 (UR polls the queue every 8 ms); a program
# that waits for a part it has lost (a counter read wrongly) stops here (about twice that), not after minutes
STEP_LIMIT = 200_000
PAST_END_MM = 40.0  # the part_past_the_window case: this far past the window's end when the program reads it
DECISION_S = 1.0  # about when the program first reads the queue (after its home move and the gripper's release)
COUNTER_BITS = 16  # the count the program reads: UR's filtered count [0; 65536[ (URScript manual), a 16-bit group
SCENARIOS = {
    "start_away": "",
    "start_mid_cycle": "",  # the arm where a stopped cycle left it: at the place
    "gripper_silent": "",
    "gripper_stuck": "",
    "device_late": "the belt's parts come at random gaps, speeds and a varying speed in every case",
    "device_silent": "a belt that brings no part is the line waiting: the program waits for the next part or the "
    "line's stop, as it should",
    "reading_out_of_range": "",  # the camera reports a part outside x_range_mm
}
SCENARIO_OF = {
    "start_away": "start_away",
    "start_mid_cycle": "start_mid_cycle",
    "gripper_silent": "gripper_silent",
    "gripper_stuck": "gripper_stuck",
    "part_out_of_range": "reading_out_of_range",
}


@dataclass(frozen=True)
class BeltCase:
    """A run: the belt (speed, wobble, where the counter starts), the parts the camera sees, how the gripper
    answers and where the arm starts."""

    category: str
    belt: Belt
    parts: tuple[Part, ...]
    robot_zero: int = 0  # the controller's own encoder against the PLC's counter
    gripper: str = "prompt"
    start: str = "home"

    @property
    def scenario(self) -> str:
        return SCENARIO_OF.get(self.category, "nominal")


def cases(cell, seed: int = 0) -> list[BeltCase]:
    """Belts at a constant and a varying speed, the counter starting just below its wrap (it rolls over
    during the picks), parts at random places across the belt and random gaps, and a part that comes
    right behind another (it has left the window before the arm is free: skipped)."""
    rng = random.Random(seed)
    conveyor, pick = conveyor_of(cell), conveyor_of(cell).pick
    e = conveyor.counts_per_mm
    span = 2**COUNTER_BITS
    # the counter wraps about 3,000 counts after the camera saw the first part (0.5 s, at 80 mm/s): between
    # the count it reports and the counts the program reads while the part travels to the window
    ahead = 3000 + abs(e) * 80.0 * 0.5
    near_wrap = round(span - ahead) if e > 0 else round(ahead)
    out = []
    for category, speed, wobble, start in (
        ("constant_speed", 60.0, 0.0, rng.randrange(span)),
        ("varying_speed", 60.0, 0.4, rng.randrange(span)),
        ("rollover", 80.0, 0.0, near_wrap),
    ):
        speed = min(speed, pick.belt_speed_max_mm_s / (1.0 + wobble))  # never faster than the cell says
        belt = Belt(speed, e, COUNTER_BITS, start, wobble, period_s=5.0)
        parts, t = [], 0.5
        for seq in range(1, 5):
            parts.append(_random_part(rng, pick, seq, t))
            t += rng.uniform(9.0, 14.0)
        out.append(BeltCase(category, belt, tuple(parts), rng.randrange(-(2**30), 2**30)))
    belt = Belt(min(70.0, pick.belt_speed_max_mm_s), e, COUNTER_BITS, rng.randrange(span))
    # parts 2 and 3 come right behind part 1: while the arm works on it they travel on (part 2 too late for
    # an intercept or past the window's end, part 3 past the end when the program takes it); part 4 later
    late = tuple(_random_part(rng, pick, seq, seen) for seq, seen in ((1, 0.5), (2, 1.0), (3, 1.5), (4, 20.0)))
    out.append(BeltCase("part_too_late", belt, late, rng.randrange(-(2**30), 2**30)))
    # the belt at its fastest (the cell's belt_speed_max_mm_s): parts 1.5 s apart reach the window's end
    # while the arm still works
    fast = Belt(pick.belt_speed_max_mm_s, e, COUNTER_BITS, rng.randrange(span))
    quick = tuple(_random_part(rng, pick, seq, seen) for seq, seen in ((1, 0.5), (2, 2.0), (3, 3.5), (4, 12.0)))
    out.append(BeltCase("fast_belt", fast, quick, rng.randrange(-(2**30), 2**30)))
    first = out[0]
    one = replace(first, parts=first.parts[:1])
    # a part the camera saw while the line stood still before the program started: when the program reads it, it
    # is PAST_END_MM beyond the window's end (the program must skip it, not chase it)
    slow = replace(first.belt, wobble=0.0)
    seen = -(pick.window_mm[1] + PAST_END_MM + conveyor.camera_offset_mm) / slow.speed_mm_s + DECISION_S
    out.append(replace(one, category="part_past_the_window", belt=slow, parts=(replace(one.parts[0], seen_s=seen),)))
    (x0, x1), _ = pick.x_range_mm, pick.z_range_mm
    wrong = replace(one.parts[0], x=x1 + 0.5 * (x1 - x0))
    out += [
        replace(one, category="start_away", start="away"),
        replace(one, category="start_mid_cycle", start="mid_cycle"),
        replace(one, category="gripper_silent", gripper="silent"),
        replace(one, category="gripper_stuck", gripper="stuck"),
        replace(one, category="part_out_of_range", parts=(wrong,)),
    ]
    return out


def _random_part(rng, pick, seq: int, seen_s: float) -> Part:
    (x0, x1), (z0, z1) = pick.x_range_mm, pick.z_range_mm
    return Part(seq, seen_s, rng.uniform(x0, x1), rng.uniform(z0, z1))


def setup(cell, target_name: str, case: BeltCase) -> Setup:
    target = get_target(target_name)
    wiring = conveyor_of(cell).pick.encoder_inputs.get(target_name)  # the installation: A and B as the cell says
    line = BeltLine(
        case.belt,
        list(case.parts),
        bus_for(target, facts(target)),
        robot_zero=case.robot_zero,
        wiring=None if not wiring else tuple(wiring),
    )
    output = signal_name(target, "output", cell.io.output[target_name])
    feedback = signal_name(target, "input", cell.io.feedback[target_name])
    gripper = Gripper(output, feedback, cell.io.value, case.gripper)
    return Setup({}, (line, gripper), {feedback: False}, _start_joints(cell, target_name, case), step_limit=STEP_LIMIT)


def _start_joints(cell, target_name: str, case: BeltCase):
    robot = cell.robot
    if robot is None or target_name not in robot.arms:
        return None
    home = np.asarray(robot.home[target_name], dtype=float)
    if case.start == "away":
        return home + np.array(START_AWAY_DEG)
    if case.start == "mid_cycle":  # at the place, where a cycle stopped after a release leaves the arm
        arm = robot.arms[target_name]
        flange = solve.flange_poses(conveyor_of(cell).pick.place.matrix(), robot.tool.tcp2flange)
        joints, _ = solve.nearest(arm, solve.branches(arm, flange), home)
        return joints
    return home


def judge(cell, target_name: str, case: BeltCase, trace, setup: Setup) -> Judgement:
    """Where the program stops (the restart rule, the gripper's silences, a bad reading), else every part
    judged where it really is (codegen/kinds/conveyor/judge.py) and every move against the pick plan."""
    target = get_target(target_name)
    line = setup.devices[0]
    emitter = Emitter(target)
    output = signal_name(target, "output", cell.io.output[target_name])
    home = home_move(cell, target_name)
    mode = conveyor_of(cell).pick.tracking[target_name]
    message = refuses_start(cell, target, case)
    if message is not None:
        return Judgement([Expectation(message, output_names=frozenset({output}))])
    first = [] if home is None else [_home(cell, home)]
    events = [o for o in trace.outputs if o.name == output]
    closes = [o for o in events if o.value == cell.io.value]
    opens = [o for o in events if o.value != cell.io.value][1:]
    names = frozenset({output})
    if case.category == "part_out_of_range":  # the camera's reading is refused before the arm moves for it
        outputs = plan.outputs(cell, output, [], [], True)
        return Judgement([Expectation(emitter.string(BAD_READING), tuple(first), outputs, output_names=names)])
    stops = {"gripper_silent": (NO_FEEDBACK, plan.GRIP[mode]), "gripper_stuck": (NOT_RELEASED, plan.RELEASE[mode])}
    if case.category in stops:  # the first part's moves up to the grip (never confirmed) or the release (never)
        reason, count = stops[case.category]
        moves = [plan.planned(segment, cell) for segment in plan.PICK[mode][:count]]
        after = len(first) + plan.GRIP[mode]
        outputs = [*plan.outputs(cell, output, [], [], True)]
        outputs.append(PlannedOutput(output, cell.io.value, after, "on the part"))
        if case.category == "gripper_stuck":
            at = len(first) + plan.RELEASE[mode]
            outputs.append(PlannedOutput(output, not cell.io.value, at, "at the place"))
        message = emitter.string(halt_message(cell, reason, None, 0))
        return Judgement([Expectation(message, (*first, *moves), tuple(outputs), output_names=names)])
    problem, pos, rot = judge_parts(cell, target_name, case, trace, line, output)
    if problem is not None:
        return Judgement([], problem=problem)
    moves = plan.lay_over(cell, mode, len(first), trace.moves, closes, opens)
    if isinstance(moves, str):
        return Judgement([], problem=moves)
    skipped = sum(1 for m in trace.messages if m.startswith((SKIPPED, TOO_LATE)))
    outputs = plan.outputs(cell, output, closes, opens, True)
    expected = Expectation(None, tuple(first) + tuple(moves), outputs, output_names=names)
    return Judgement([expected], figures=(len(case.parts) - skipped, skipped), errors=([pos], [rot]))


def _home(cell, home) -> PlannedMove:
    percent = cell.motion.joint_speed_percent
    return PlannedMove("home", home[0].kind, home[0].tcp2base, True, None, 0.0, percent, joints=home[1])


@dataclass
class BeltFigures:
    picked: int = 0
    skipped: int = 0


def legacy_summary(row) -> dict:
    """A row as `codegen verify --json` lists it under "conveyors"."""
    s = row.summary()
    figures = row.figures or BeltFigures()
    return {
        "target": row.target,
        "files": row.files,
        "cases": row.cases,
        "mismatches": row.mismatches,
        "parts_picked": figures.picked,
        "parts_skipped": figures.skipped,
        "pos_max_mm": s["position_error_mm"]["max"],
        "rot_max_deg": s["orientation_error_deg"]["max"],
        "first_mismatches": row.first_mismatches,
    }


def report_lines(rows: list) -> list[str]:
    lines = ["conveyor  target    cases  fail  picked  skipped"]
    for r in rows:
        figures = r.figures or BeltFigures()
        counts = f"{r.cases:6d} {r.mismatches:5d} {figures.picked:7d} {figures.skipped:8d}"
        lines.append(f"{'belt':9} {r.target:8} {counts}")
    return lines
