"""Verify pick-from-belt programs: each case run against a simulated belt, judged by where each part really is."""

from __future__ import annotations

import random
import time
from dataclasses import dataclass

from codegen import sections
from codegen.controllers import get_target
from codegen.kinds.conveyor.judge import judge
from codegen.kinds.conveyor.program import SKIPPED, TOO_LATE
from codegen.kinds.conveyor.section import conveyor_of, facts
from codegen.model.io import signal_name
from codegen.robot.expect import arm_of
from codegen.sim.belt import Belt, ConveyorLine, Part
from codegen.sim.bus import bus_for
from codegen.sim.gripper import Gripper
from codegen.verify import tally

# a run's statements: the bundled cell's longest case takes 86,000 (UR polls the queue every 8 ms); a program
# that waits for a part it has lost (a counter read wrongly) stops here (about twice that), not after minutes
STEP_LIMIT = 200_000
COUNTER_BITS = 16  # the count the program reads: UR's filtered count [0; 65536[ (URScript manual), a 16-bit group


@dataclass(frozen=True)
class BeltCase:
    """A run: the belt (speed, wobble, where the counter starts) and the parts the camera sees."""

    category: str
    belt: Belt
    parts: tuple[Part, ...]
    robot_zero: int = 0  # the controller's own encoder against the PLC's counter


@dataclass
class ConveyorReport(sections.SectionReport):
    picked: int = 0
    skipped: int = 0

    def figures(self) -> dict:
        return {
            "parts_picked": self.picked,
            "parts_skipped": self.skipped,
            "pos_max_mm": self.max_pos_mm,
            "rot_max_deg": self.max_rot_deg,
        }


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
    return out


def _random_part(rng, pick, seq: int, seen_s: float) -> Part:
    (x0, x1), (z0, z1) = pick.x_range_mm, pick.z_range_mm
    return Part(seq, seen_s, rng.uniform(x0, x1), rng.uniform(z0, z1))


def run_case(cell, target_name: str, program, case: BeltCase):
    target = get_target(target_name)
    line = ConveyorLine(case.belt, list(case.parts), bus_for(target, facts(target)), robot_zero=case.robot_zero)
    output = signal_name(target, "output", cell.io.output[target_name])
    feedback = signal_name(target, "input", cell.io.feedback[target_name])
    gripper = Gripper(output, feedback, cell.io.value, "prompt")
    arm = arm_of(cell, target_name)
    trace = program.run(
        {},
        devices=(line, gripper),
        signals={feedback: False},
        arm=arm,
        start_joints=None if arm is None else cell.robot.home[target_name],
        step_limit=STEP_LIMIT,
    )
    return trace, line, output


def verify_conveyor(
    cell, target_name: str, program, files: list[str], seed: int = 0, first_only: bool = False
) -> ConveyorReport:
    """Every case on one target's program (first_only: stop at the first mismatch)."""
    report = ConveyorReport(target_name, files)
    started = time.perf_counter()
    for case in cases(cell, seed):
        try:
            trace, line, output = run_case(cell, target_name, program, case)
            problem, pos, rot = judge(cell, target_name, case, trace, line, output)
            skipped = sum(1 for m in trace.messages if m.startswith((SKIPPED, TOO_LATE)))
            picked = len(case.parts) - skipped
        except Exception as exc:  # a run error is this case's mismatch
            problem, pos, rot, skipped, picked = f"run error: {exc}", 0.0, 0.0, 0, 0
        report.skipped += skipped
        report.picked += picked
        if tally(report, problem, pos, rot, case.category) and first_only:
            break
    report.seconds = time.perf_counter() - started
    return report


def fresh_program(cell, target_name: str):
    """The cell's pick program for a target, rendered and parsed: (program, file names); None: none."""
    from codegen.kinds.conveyor.program import conveyor_file_names, picks_on

    target = get_target(target_name)
    if not picks_on(cell, target):
        return None
    return sections.fresh_program(cell, target_name, conveyor_file_names(cell, target))


def _row(r: ConveyorReport) -> str:
    return (
        f"{'belt':9} {r.target:8} {r.cases:6d} {r.mismatches:5d} {r.picked:7d} {r.skipped:8d}  "
        f"{r.max_pos_mm:10.2e}  {r.max_rot_deg:11.2e}"
    )


def conveyor_section(cell, files: tuple, targets: tuple, seed: int) -> tuple[sections.Section | None, tuple]:
    """The pick programs among FILES (or fresh ones) verified against simulated belts; the other files
    are returned."""
    from codegen.kinds.conveyor.program import conveyor_file_names

    if conveyor_of(cell) is None or conveyor_of(cell).pick is None:
        return None, files

    def verify(cell, name, program, names):
        return verify_conveyor(cell, name, program, names, seed)

    reports, rest = sections.collect(
        cell, files, targets, lambda target: conveyor_file_names(cell, target), fresh_program, verify
    )
    header = "conveyor  target    cases  fail  picked  skipped  pos max mm  rot max deg"
    passed, failed = "every part gripped where it is", "MISMATCHES in the conveyor programs"
    return sections.Section(reports, header, _row, passed, failed), rest
