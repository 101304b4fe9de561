"""Verify pick-from-belt programs: each case run against a simulated belt, judged by where each part really is."""

from __future__ import annotations

import math
import random
import time
from dataclasses import dataclass, field

import numpy as np

from codegen.controllers import get_target
from codegen.conveyor.belt import Belt, ConveyorLine, Part, part_pose, part_y
from codegen.conveyor.bus import bus_for
from codegen.conveyor.program import SKIPPED, STOPPED, TOO_LATE, lead_seconds
from codegen.poses import rotmat_from_zyx_deg
from codegen.robot.expect import arm_of
from codegen.signals import Gripper, signal_name
from codegen.verify import TOLERANCES, _pose_errors

COUNTER_BITS = 16  # the count the program reads: UR's filtered count [0; 65536[ (URScript manual), a 16-bit group


@dataclass(frozen=True)
class BeltCase:
    """A run: the belt (speed, wobble, where the counter starts) and the parts the camera sees."""

    category: str
    belt: Belt
    parts: tuple[Part, ...]


@dataclass
class ConveyorReport:
    target: str
    files: list[str]
    cases: int = 0
    mismatches: int = 0
    picked: int = 0
    skipped: int = 0
    max_pos_mm: float = 0.0
    max_rot_deg: float = 0.0
    first_mismatches: list[str] = field(default_factory=list)
    seconds: float = 0.0

    def summary(self) -> dict:
        return {
            "target": self.target,
            "files": self.files,
            "cases": self.cases,
            "mismatches": self.mismatches,
            "parts_picked": self.picked,
            "parts_skipped": self.skipped,
            "pos_max_mm": self.max_pos_mm,
            "rot_max_deg": self.max_rot_deg,
            "first_mismatches": self.first_mismatches,
        }


def position_tolerance_mm(counts_per_mm: float, numbers: str) -> float:
    """What the program can know of a part's place: it sees whole counts, once where the part is when
    tracking starts and once in the tracking offset (each within one count of the travel), so the
    gripper may sit up to 2 / |E| mm off along the belt; plus the controller's float arithmetic."""
    return 2.0 / abs(counts_per_mm) + TOLERANCES[numbers][0]


def cases(cell, seed: int = 0) -> list[BeltCase]:
    """Belts at a constant and a varying speed, the counter starting just below its wrap (it rolls over
    during the picks), parts at random places across the belt and random gaps, and a part that comes
    right behind another (it has left the window before the arm is free: skipped)."""
    rng = random.Random(seed)
    conveyor, pick = cell.conveyor, cell.conveyor.pick
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
        belt = Belt(speed, e, COUNTER_BITS, start, wobble, period_s=5.0)
        parts, t = [], 0.5
        for seq in range(1, 5):
            parts.append(_random_part(rng, pick, seq, t))
            t += rng.uniform(9.0, 14.0)
        out.append(BeltCase(category, belt, tuple(parts)))
    belt = Belt(70.0, e, COUNTER_BITS, rng.randrange(span))
    # parts 2 and 3 come right behind part 1: while the arm works on it they travel on (part 2 too late for
    # an intercept or past the window's end, part 3 past the end when the program takes it); part 4 later
    late = tuple(_random_part(rng, pick, seq, seen) for seq, seen in ((1, 0.5), (2, 1.0), (3, 1.5), (4, 20.0)))
    out.append(BeltCase("part_too_late", belt, late))
    return out


def _random_part(rng, pick, seq: int, seen_s: float) -> Part:
    (x0, x1), (z0, z1) = pick.x_range_mm, pick.z_range_mm
    return Part(seq, seen_s, rng.uniform(x0, x1), rng.uniform(z0, z1))


def run_case(cell, target_name: str, program, case: BeltCase):
    target = get_target(target_name)
    line = ConveyorLine(case.belt, list(case.parts), bus_for(target))
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
        step_limit=2_000_000,
    )
    return trace, line, output


def judge(
    cell, target_name: str, case: BeltCase, trace, line: ConveyorLine, output: str
) -> tuple[str | None, float, float]:
    """Every part taken once and in order; a part is skipped exactly when it was past the window's end
    when the program took it (or had passed it by the time the program took the next); each picked part
    is gripped where it really is at that moment (float64: the belt's travel since the camera saw it),
    inside the window; each is put down at the place; the program ends at the line's stop."""
    target = get_target(target_name)
    conveyor, pick = cell.conveyor, cell.conveyor.pick
    camera_y, (start, end) = -conveyor.camera_offset_mm, pick.window_mm
    frame = conveyor.frame()
    grip = np.eye(4)
    grip[:3, :3] = rotmat_from_zyx_deg(*pick.tool_orientation)
    intercepts = pick.tracking[target_name] == "intercept"
    # an intercepting arm meets the part where it predicts it: the gripper's capture range is the bound
    pos_tol = pick.capture_mm if intercepts else position_tolerance_mm(conveyor.counts_per_mm, target.numbers)
    rot_tol = TOLERANCES[target.numbers][1]
    worst_pos = worst_rot = 0.0
    if trace.halted:
        return f"stopped: {trace.halt_message!r}", 0.0, 0.0
    if list(line.taken) != [p.seq for p in case.parts]:
        return f"parts taken {list(line.taken)}, expected {[p.seq for p in case.parts]} (each once, in order)", 0.0, 0.0
    skipped = {int(m[len(SKIPPED) :]) for m in trace.messages if m.startswith(SKIPPED)}
    too_late = {
        int(m[len(TOO_LATE) :]): t
        for m, t in zip(trace.messages, trace.message_times, strict=True)
        if m.startswith(TOO_LATE)
    }
    for seq, t in too_late.items():  # the part was already too close to the intercept point to come down in time
        part = next(p for p in case.parts if p.seq == seq)
        latest = pick.intercept_mm - lead_seconds(cell) * case.belt.speed_mm_s * (1.0 + abs(case.belt.wobble))
        if part_y(case.belt, part, camera_y, t) < latest - pick.capture_mm:
            y = part_y(case.belt, part, camera_y, t)
            return f"part {seq} given up as too late at y {y:.1f} mm, in time for the intercept", 0.0, 0.0
    skipped |= set(too_late)
    closes = [o for o in trace.outputs if o.name == output and o.value == cell.io.value]
    opens = [o for o in trace.outputs if o.name == output and o.value != cell.io.value][1:]  # after the first
    picked = [p for p in case.parts if p.seq not in skipped]
    if len(closes) != len(picked) or len(opens) != len(picked):
        return f"{len(closes)} grips and {len(opens)} releases for {len(picked)} parts picked", 0.0, 0.0
    takes = [line.taken[p.seq] for p in case.parts] + [math.inf]
    for i, part in enumerate(case.parts):
        # where the program, counting whole counts, finds the part when it takes it
        delta = (case.belt.count(takes[i]) - case.belt.count(part.seen_s)) % 2**case.belt.counter_bits
        counted_y = camera_y + _signed(delta, case.belt.counter_bits) / conveyor.counts_per_mm
        past_end = counted_y > end
        if part.seq in too_late:
            continue
        if part.seq in skipped:
            later = takes[i + 1] if math.isfinite(takes[i + 1]) else takes[i] + 60.0
            if not past_end and part_y(case.belt, part, camera_y, later) <= end:
                return f"part {part.seq} skipped while it was still in the window", worst_pos, worst_rot
        elif past_end:
            return f"part {part.seq} picked although it was past the window's end ({counted_y:.1f} mm)", 0, 0
    for part, close, release in zip(picked, closes, opens, strict=True):
        y = part_y(case.belt, part, camera_y, close.time)
        if not start - pos_tol <= y <= end + pos_tol:
            return (
                f"part {part.seq} gripped at y {y:.2f} mm, outside the window [{start:g}, {end:g}]",
                worst_pos,
                worst_rot,
            )
        want = part_pose(frame, case.belt, part, camera_y, close.time, grip)
        pos, rot = _pose_errors(close.tcp2base.tolist(), want.tolist())
        worst_pos, worst_rot = max(worst_pos, pos), max(worst_rot, rot)
        if pos > pos_tol or rot > rot_tol:
            return (
                f"part {part.seq} gripped {pos:.4f} mm, {rot:.5f} deg from where it is (line {close.line}; "
                f"tolerance {pos_tol:.4f} mm)",
                worst_pos,
                worst_rot,
            )
        pos, rot = _pose_errors(release.tcp2base.tolist(), pick.place.matrix().tolist())
        if pos > TOLERANCES[target.numbers][0] or rot > rot_tol:
            return f"part {part.seq} released {pos:.4f} mm, {rot:.5f} deg from the place", worst_pos, worst_rot
    if not trace.messages or trace.messages[-1] != STOPPED:
        return f"the program did not end at the line's stop (last message {trace.messages[-1:]})", worst_pos, worst_rot
    return None, worst_pos, worst_rot


def _signed(delta: int, bits: int) -> int:
    """A counter difference taken the short way round (the program's unwinding)."""
    span = 2**bits
    return delta - span if delta > span // 2 else delta


def verify_conveyor(cell, target_name: str, program, files: list[str], seed: int = 0) -> ConveyorReport:
    report = ConveyorReport(target_name, files)
    started = time.perf_counter()
    for case in cases(cell, seed):
        try:
            trace, line, output = run_case(cell, target_name, program, case)
            problem, pos, rot = judge(cell, target_name, case, trace, line, output)
            skipped = sum(1 for m in trace.messages if m.startswith((SKIPPED, TOO_LATE)))
        except Exception as exc:  # a run error is this case's mismatch
            problem, pos, rot, skipped = f"run error: {exc}", 0.0, 0.0, 0
        report.cases += 1
        report.skipped += skipped
        report.picked += len(case.parts) - skipped
        report.max_pos_mm, report.max_rot_deg = max(report.max_pos_mm, pos), max(report.max_rot_deg, rot)
        if problem is not None:
            report.mismatches += 1
            if len(report.first_mismatches) < 5:
                report.first_mismatches.append(f"{case.category}: {problem}")
    report.seconds = time.perf_counter() - started
    return report


def fresh_program(cell, target_name: str):
    """The cell's pick program for a target, rendered and parsed: (program, file names); None: none."""
    from codegen.conveyor.program import conveyor_file_names, picks_on
    from codegen.render import render
    from codegen.verify_runs import load_program

    target = get_target(target_name)
    if not picks_on(cell, target):
        return None
    names = conveyor_file_names(cell, target)
    files = {f.relpath.rsplit("/", 1)[1]: f for f in render(cell, [target_name])}
    main = files[names[0]]
    companions = {"." + n.rsplit(".", 1)[1]: files[n].text for n in names[1:]}  # a data file beside it
    return load_program(target, main.text, f"<fresh>/{main.relpath}", companions), names


@dataclass
class ConveyorSection:
    """`codegen verify`'s part for the pick-from-belt programs."""

    reports: list[ConveyorReport]

    @property
    def ok(self) -> bool:
        return all(r.mismatches == 0 for r in self.reports)

    def summaries(self) -> list[dict]:
        return [r.summary() for r in self.reports]

    def lines(self) -> list[str]:
        lines = ["conveyor  target    cases  fail  picked  skipped  pos max mm  rot max deg"]
        for r in self.reports:
            lines.append(
                f"{'belt':9} {r.target:8} {r.cases:6d} {r.mismatches:5d} {r.picked:7d} {r.skipped:8d}  "
                f"{r.max_pos_mm:10.2e}  {r.max_rot_deg:11.2e}"
            )
            lines += [f"  {r.target}: {m}" for m in r.first_mismatches]
        verdict = "every part gripped where it is" if self.ok else "MISMATCHES in the conveyor programs"
        return [*lines, f"verify: {verdict}"]


def conveyor_section(cell, files: tuple, targets: tuple, seed: int) -> tuple[ConveyorSection | None, tuple]:
    """The pick programs among FILES (or fresh ones) verified against simulated belts; the other files
    are returned."""
    from pathlib import Path

    from codegen.conveyor.program import conveyor_file_names
    from codegen.verify_runs import file_source

    if cell.conveyor is None or cell.conveyor.pick is None:
        return None, files
    names = list(targets) or list(cell.targets)
    reports, rest = [], list(files)
    for name in names:
        target = get_target(name)
        own = conveyor_file_names(cell, target)
        if files:
            for f in [f for f in rest if Path(f).name in own]:
                rest.remove(f)  # a data file is read with its program (file_source)
                if Path(f).name == own[0]:
                    source = file_source(name, Path(f))
                    reports.append(verify_conveyor(cell, name, source.load(), list(source.files), seed))
            continue
        fresh = fresh_program(cell, name)
        if fresh is not None:
            reports.append(verify_conveyor(cell, name, *fresh, seed))
    return ConveyorSection(reports), tuple(rest)
