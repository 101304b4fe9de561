"""Run programs in the interpreter on many readings and compare each trace with the reference."""

from __future__ import annotations

import math
import random
import re
import time
from array import array
from dataclasses import dataclass, field, replace
from functools import lru_cache
from pathlib import Path

import numpy as np

from codegen.controllers import Target, get_target, target_of_suffix
from codegen.dialects import get_dialect
from codegen.dialects.core.machine import DEFAULT_STEP_LIMIT, Program, frozen_heap
from codegen.dialects.core.values import RunError, StepLimitError
from codegen.emit import Emitter
from codegen.guard import (
    NO_ANSWER,
    NO_FEEDBACK,
    NOT_AT_HOME,
    NOT_RELEASED,
    UNKNOWN_STATION,
    UNKNOWN_STATION_TEXT,
    halt_message,
)
from codegen.kinds.stations.base import Case
from codegen.model import io as signals
from codegen.model import vision
from codegen.model.cell import STATION_ID_MAX, Cell, Station, TaughtPose
from codegen.poses import native_values
from codegen.protocol import get_kind, station_kinds
from codegen.reference import ExpectedTrace
from codegen.robot.expect import ArmStats, arm_of, arm_problem, home_move, tool_inputs
from codegen.robot.region import station_plan
from codegen.sim.gripper import Gripper
from codegen.sim.vision_pc import VisionPC

# Tolerances from the numeric model (issue 4): a float32 controller over a +-2,000 mm workspace
# stores positions with a step of 1.2e-4 mm and angles with 1e-7 rad; a handful of such roundings
# through the correction stays far below these bounds, a wrong formula far above them.
TOLERANCES = {"float32": (0.005, 0.001), "float64": (1e-9, 1e-9)}  # mm, deg


def tally(report, problem: str | None, pos: float, rot: float, label: str) -> bool:
    """Count one case of a program kind's own verify (pallets, conveyors) in its report: the case, the worst
    errors, and a mismatch with the first five named; True when the case mismatched."""
    report.cases += 1
    report.max_pos_mm, report.max_rot_deg = max(report.max_pos_mm, pos), max(report.max_rot_deg, rot)
    if problem is None:
        return False
    report.mismatches += 1
    if len(report.first_mismatches) < 5:
        report.first_mismatches.append(f"{label}: {problem}")
    return True
NUMBER = re.compile(r"(?<![\w.])[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?|(?<!\w)[-+]?(?:nan|inf)\b")


@dataclass(frozen=True)
class UnknownStation:
    """A station id the cell does not have: every program must halt with the unknown-station message."""

    station_id: int


@dataclass
class TargetReport:
    target: str
    files: list[str]
    cases: int = 0
    mismatches: int = 0
    halts: int = 0
    boundary: int = 0
    moves: int = 0
    # every compared move's errors, 8 bytes each (a list of floats takes four times that: issue 16's memory)
    pos_errors: array = field(default_factory=lambda: array("d"))
    rot_errors: array = field(default_factory=lambda: array("d"))
    first_mismatches: list[str] = field(default_factory=list)
    seconds: float = 0.0
    categories: dict[str, int] = field(default_factory=dict)
    unknown_ids: int = 0  # ids of the whole barcode range that are not stations, each checked to halt
    kind_stats: dict = field(default_factory=lambda: {name: kind.new_stats() for name, kind in station_kinds().items()})
    arm: ArmStats = field(default_factory=ArmStats)

    def summary(self) -> dict:
        def stats(values):
            if not values:
                return {"max": 0.0, "p99": 0.0}
            arr = np.frombuffer(values, dtype=float) if isinstance(values, array) else np.array(values)
            return {"max": float(arr.max()), "p99": float(np.percentile(arr, 99))}

        out = {
            "target": self.target,
            "files": self.files,
            "cases": self.cases,
            "categories": self.categories,
            "mismatches": self.mismatches,
            "halts": self.halts,
            "boundary_cases": self.boundary,
            "moves_compared": self.moves,
            "position_error_mm": stats(self.pos_errors),
            "orientation_error_deg": stats(self.rot_errors),
            "seconds": self.seconds,
            "cases_per_second": self.cases / self.seconds if self.seconds else None,
            "unknown_ids_checked": self.unknown_ids,
        }
        if self.arm.moves:
            out["arm"] = self.arm.summary()
        for name, kind in station_kinds().items():  # each kind's own figures, under its name
            own = kind.summary(self.kind_stats[name])
            if own is not None:
                out[name] = own
        out["first_mismatches"] = self.first_mismatches
        return out


# --- programs --------------------------------------------------------------------------------


def target_of_file(path: Path) -> str:
    target = target_of_suffix(path.suffix)
    if target is None:
        raise ValueError(f"{path}: cannot tell the target from the suffix; use --target")
    return target.name


def _kind_of_case(cell: Cell, reading):
    if isinstance(reading, UnknownStation):
        return None
    return get_kind(cell.station_by_id(reading.station_id).kind)


def inputs_for(cell: Cell, target: Target, reading, behaviour: str = "prompt") -> dict:
    """What the controller holds when the program starts: the vision PC's variables from the previous
    cycle (a plausible reading of the station, its request answered), the controller's numbered
    tool and the kind's own values."""
    kind = _kind_of_case(cell, reading)
    tools = tool_inputs(cell, target.name)  # the controller's numbered tool, where the program selects one
    previous, answered = _previous_reading(cell, target, reading), vision.answered(target, behaviour)
    if kind is None:
        return {**previous, **answered, **tools}
    return {**previous, **answered, **kind.inputs(cell, target, reading), **tools}


START_AWAY_DEG = (25.0, -15.0, 10.0, 0.0, 0.0, 0.0)  # the arm left away from home (start_away cases)


def start_joints(cell: Cell, target: Target, case: Case):
    """Where the arm stands when the program starts (deg): at home, away from it or at the case's
    station's taught retreat; None without an arm."""
    home = home_move(cell, target.name)
    if home is None:
        return None
    if case.start == "retreat":
        taught, _ = station_plan(cell, target.name, cell.station_by_id(case.reading.station_id))
        return next(pose.joints for pose in taught if pose.name == "retreat")
    return home[1] + (np.array(START_AWAY_DEG) if case.start == "away" else 0.0)


def _previous_reading(cell: Cell, target: Target, reading) -> dict:
    """The vision PC's variables from the previous cycle: a reading of the case's station (an unknown
    station's case: of the cell's first station)."""
    station = cell.station_by_id(reading.station_id) if _kind_of_case(cell, reading) else cell.stations[0]
    return get_kind(station.kind).previous(cell, target, station)


def _gripper_signals(cell: Cell, target_name: str) -> tuple[str, str] | None:
    """The work pose's output and feedback as the target's program names them, or None (no feedback)."""
    io, target = cell.io, get_target(target_name)
    if io is None or not io.feedback or not target.program.get("signals"):
        return None
    return (
        signals.signal_name(target, "output", io.output[target_name]),
        signals.signal_name(target, "input", io.feedback[target_name]),
    )


def run_options(cell: Cell, target: Target, case: Case) -> dict:
    """Keyword arguments of Program.run for a case: its devices, where the arm starts and, with a gripper,
    its feedback on (the gripper closed from the last cycle)."""
    options = {"devices": devices_for(cell, target, case), "start_joints": start_joints(cell, target, case)}
    gripper = _gripper_signals(cell, target.name)
    if gripper is not None:
        options["signals"] = {gripper[1]: True}
    return options


def devices_for(cell: Cell, target: Target, case: Case) -> tuple:
    """The simulated devices of a case: the vision PC, and the gripper where the cell has a work-pose
    signal with feedback."""
    out: tuple = (vision_pc(cell, target, case),)
    gripper = _gripper_signals(cell, target.name)
    if gripper is not None:
        out += (Gripper(*gripper, cell.io.value, case.gripper),)
    return out


def vision_pc(cell: Cell, target: Target, case: Case) -> VisionPC:
    """The simulated vision PC of a case: it answers with the case's reading, by the case's behaviour."""
    kind = _kind_of_case(cell, case.reading)
    if kind is None:
        answer = {target.program["inputs"]["station"]: case.reading.station_id}
        camera = None
    else:
        answer, camera = kind.answer(cell, target, case.reading), kind.camera(cell, case.reading)
    latency = vision.latency(cell.vision, case.vision)
    previous = _previous_reading(cell, target, case.reading)
    return VisionPC.for_target(target, answer, camera, case.vision, latency, previous)


# --- cases -----------------------------------------------------------------------------------


def edge_cell(cell: Cell) -> Cell:
    """The cell plus one station whose taught poses sit on the conventions' edges."""
    edge_poses_xyzabc = {
        "yaw_wraps_plus": (520.0, 80.0, 310.0, 179.99, 12.0, 171.0),
        "yaw_wraps_minus": (530.0, 60.0, 300.0, -179.99, -8.0, -169.0),
        "b_plus_90": (540.0, 40.0, 320.0, 30.0, 90.0, 0.0),
        "b_minus_90": (510.0, 90.0, 330.0, -45.0, -89.9999, 20.0),
        "rotvec_pi": (500.0, 100.0, 300.0, 0.0, 0.0, 180.0),
        "rotvec_near_pi": (505.0, 95.0, 305.0, 0.002, 0.001, 179.998),
    }
    poses = tuple(
        TaughtPose(name, native_values(values, "xyzabc", cell.pose_format), cell.pose_format)
        for name, values in edge_poses_xyzabc.items()
    )
    new_id = max(s.id for s in cell.stations) + 1
    kind = next((k for k in station_kinds().values() if k.edge_spec() is not None), None)
    if new_id > STATION_ID_MAX or kind is None:
        return cell
    station = Station(new_id, "verify_edge_poses", poses, kind.name, kind.edge_spec())
    return replace(cell, stations=(*cell.stations, station))


def edge_only_cell(cell: Cell) -> Cell | None:
    """For a cell with an arm: its edge-case poses (which no arm need reach: they test the pose
    conventions) as a cell of their own without the arm, verified beside the cell's programs."""
    edge = edge_cell(replace(cell, robot=None))
    if cell.robot is None or len(edge.stations) == len(cell.stations):
        return None
    return replace(edge, stations=edge.stations[-1:])


def build_cases(cell: Cell, count: int, seed: int) -> list[Case]:
    """Each station's cases from its kind (one random sequence for the cell), then its first case again
    with the vision PC late, silent, replaying the last cycle, answering twice, answering another
    request or sending a late answer to the previous cycle first; then unknown stations."""
    rng = random.Random(seed)
    cases: list[Case] = []
    for station in cell.stations:
        own = get_kind(station.kind).cases(cell, station, count, rng)
        cases.extend(own)
        cases.extend(Case(f"vision_{b}", own[0].reading, b) for b in vision.BEHAVIOURS[1:] if own)
        if own and cell.io is not None and cell.io.feedback:  # the gripper never confirms, or never releases
            cases.append(Case("gripper_silent", own[0].reading, gripper="silent"))
            cases.append(Case("gripper_stuck", own[0].reading, gripper="stuck"))
    if cell.robot is not None and cases:  # the program started with the arm away from home, or at a retreat
        cases.append(Case("start_away", cases[0].reading, start="away"))
        if cell.motion.retreat_mm > 0:
            cases.append(Case("start_retreat", cases[0].reading, start="retreat"))
    known = {s.id for s in cell.stations}
    for station_id in (0, -1, max(known) + 1, STATION_ID_MAX, 99999):
        if station_id not in known:
            cases.append(Case("unknown_station", UnknownStation(station_id)))
    return cases


# --- comparison ------------------------------------------------------------------------------


def _truth_problem(cell: Cell, case: Case, reference: ExpectedTrace) -> str | None:
    kind = _kind_of_case(cell, case.reading)
    if kind is None or case.vision in vision.UNANSWERED:  # the camera's view never reaches the program
        return None
    return kind.truth_problem(cell, case.reading, reference)


def accepted_traces(cell: Cell, case: Case) -> tuple[list[ExpectedTrace], bool]:
    if case.vision in vision.UNANSWERED:  # the program must not use what it did not get: it halts at home
        return [ExpectedTrace("halt", NO_ANSWER)], False
    kind = _kind_of_case(cell, case.reading)
    if kind is None:
        return [ExpectedTrace("halt", UNKNOWN_STATION)], False
    accepted, boundary = kind.accepted(cell, case.reading)
    second = kind.second_look(case.reading) if case.vision == "twice" else None
    if second is not None:  # answered twice within one poll: either answer, used whole, is correct
        more, more_boundary = kind.accepted(cell, second)
        accepted, boundary = [*accepted, *more], boundary or more_boundary
    if case.gripper == "stuck":  # it stops at home, before it asks the vision PC
        return [ExpectedTrace("halt", NOT_RELEASED)], False
    if case.gripper == "silent":  # the station stops at its work pose, the signal set, with the message
        accepted = [
            replace(t, status="halt", reason=NO_FEEDBACK, moves=t.moves[: len(t.station.poses)])
            if t.status == "ok"
            else t
            for t in accepted
        ]
    return accepted, boundary


def _pose_errors(a: list, b: list) -> tuple[float, float]:
    """Position distance (mm) and rotation angle (deg) between two 4x4 poses given as lists; the
    angle from ||Ra - Rb||_F = 2 sqrt(2) sin(angle / 2), exact for any angle."""
    (a0, a1, a2, _), (b0, b1, b2, _) = a, b
    position = math.dist((a0[3], a1[3], a2[3]), (b0[3], b1[3], b2[3]))
    distance = math.dist(a0[:3] + a1[:3] + a2[:3], b0[:3] + b1[:3] + b2[:3])  # Frobenius norm of Ra - Rb
    return position, math.degrees(2.0 * math.asin(min(1.0, distance / (2.0 * math.sqrt(2.0)))))



def expected_message(cell: Cell, trace: ExpectedTrace, reading, emitter: Emitter) -> str:
    if trace.reason == UNKNOWN_STATION:
        return emitter.string(UNKNOWN_STATION_TEXT) + str(reading.station_id)
    if trace.reason in (NO_ANSWER, NO_FEEDBACK, NOT_AT_HOME, NOT_RELEASED):
        return emitter.string(halt_message(cell, trace.reason, None, 0))
    kind = get_kind(trace.station.kind)
    return emitter.string(kind.fitted_message(cell, trace.reason, trace.station, emitter.target.string_max))


@lru_cache(maxsize=64)
def _move_settings(target_name: str, kind: str, exact: bool, own_tool: bool, speed_mm_s, zone_mm, percent) -> dict:
    """What a target's facts and the cell's motion ask of a move (read once per target and segment,
    not per move of every case)."""
    target = get_target(target_name)
    return get_dialect(target.dialect).move_settings(
        target.program, kind, exact, own_tool, speed_mm_s, zone_mm, percent
    )


LOG_PREFIXES = tuple(prefix for kind in station_kinds().values() for prefix in kind.log_prefixes)


def _log_numbers(messages: list[str]) -> list[float]:
    out = []
    for message in messages:
        if message.startswith(LOG_PREFIXES):
            out.extend(float(n) for n in NUMBER.findall(message))
    return out


def compare(cell: Cell, target: Target, reading, expected: ExpectedTrace, got, emitter: Emitter):
    """(problem or None, position errors, orientation errors)."""
    pos_tol, rot_tol = TOLERANCES[target.numbers]
    if expected.status == "halt":
        if not got.halted:
            return f"expected a halt ({expected.reason}), program did not halt ({len(got.moves)} moves)", [], []
        want = expected_message(cell, expected, reading, emitter)
        if got.halt_message != want:
            return f"halt message {got.halt_message!r}, expected {want!r}", [], []
    elif got.halted:
        return f"unexpected halt: {got.halt_message!r}", [], []
    home = home_move(cell, target.name)
    if expected.reason == NOT_AT_HOME:
        home = None  # it stops before its first motion
    moves = expected.moves if home is None else (home[0], *expected.moves)
    if home is not None and expected.status == "ok" and cell.motion.return_home:
        moves = (*moves, home[0])  # and home again after the station
    if len(got.moves) != len(moves):
        return f"{len(got.moves)} moves, expected {len(moves)}", [], []
    own_tool = cell.robot is not None and cell.robot.tool_given
    pos_errors, rot_errors = [], []
    for i, (g, e) in enumerate(zip(got.moves, moves, strict=True)):
        if g.kind != e.kind:
            return f"move {i + 1} ({e.pose_name}) is {g.kind}, expected {e.kind}", [], []
        for key, want in _move_settings(
            target.name, e.kind, e.exact, own_tool, e.speed_mm_s, e.zone_mm, e.joint_percent
        ).items():
            have = g.settings.get(key)
            numbers = isinstance(want, float) and isinstance(have, float)
            if have != want and not (numbers and math.isclose(have, want, rel_tol=1e-6)):  # float32 values
                exact = " (the arm must stop exactly at this pose)" if e.exact else ""
                return f"move {i + 1} ({e.pose_name}, line {g.line}): {key} {have}, expected {want}{exact}", [], []
        pos, rot = _pose_errors(g.tcp2base.tolist(), e.tcp2base.tolist())
        pos_errors.append(pos)
        rot_errors.append(rot)
        if not pos <= pos_tol or not rot <= rot_tol:
            return (
                (
                    f"move {i + 1} ({e.pose_name}, line {g.line}): position error {pos:.6f} mm, "
                    f"orientation error {rot:.6f} deg (tolerance {pos_tol} mm, {rot_tol} deg)"
                ),
                pos_errors,
                rot_errors,
            )
    problem = output_problem(cell, target, expected, got, 0 if home is None else 1)
    if problem is not None:
        return problem, pos_errors, rot_errors
    if home is not None:
        problem = arm_problem(cell, target.name, expected, moves, got.moves, home[1])
        if problem is not None:
            return problem, pos_errors, rot_errors
    if expected.status == "halt":
        return None, pos_errors, rot_errors
    numbers = _log_numbers(got.messages)
    want = list(expected.logged)
    decimals = target.program.get("log_decimals")
    log_tol = 0.5 * 10.0**-decimals + 1e-3 if decimals is not None else pos_tol
    if len(numbers) != len(want):
        return f"log line has {len(numbers)} numbers, expected {len(want)}: {got.messages!r}", [], []
    names = _kind_of_case(cell, reading).log_names
    for name, g, w in zip(names, numbers, want, strict=True):
        if not abs(g - w) <= log_tol:
            return f"logged {name} = {g}, expected {w:.6f} (tolerance {log_tol})", pos_errors, rot_errors
    return None, pos_errors, rot_errors


def describe_case(cell: Cell, reading) -> str:
    kind = _kind_of_case(cell, reading)
    return f"station {reading.station_id}" if kind is None else kind.describe(reading)


def verify(
    cell: Cell,
    targets: list[str],
    programs: dict[str, tuple[Program, list[str]]],
    cases: list[Case],
    progress=None,
    verify_cell: Cell | None = None,
    step_limit: int = DEFAULT_STEP_LIMIT,
) -> list[TargetReport]:
    """Run every case on every target's program; verify_cell is the cell the programs were made from.
    A run that reaches the step limit (a runaway loop) is a mismatch and ends that target's cases:
    the next ones would run as long."""
    model = verify_cell or cell
    expectations = [(case, *accepted_traces(model, case)) for case in cases]
    # What the physical situation demands of a correct cell, independent of the cell's own model:
    # a cell whose reference contradicts it (a wrong camera sign) fails on every target.
    truth = [_truth_problem(model, case, accepted[0]) for case, accepted, _ in expectations]
    with frozen_heap():
        return [
            _verify_target(model, name, programs[name], expectations, truth, progress, step_limit) for name in targets
        ]


def _verify_target(model: Cell, name: str, program_files, expectations, truth, progress, step_limit) -> TargetReport:
    """One target's program on every case, compared with the cases' accepted traces."""
    target = get_target(name)
    program, files = program_files
    emitter = Emitter(target)
    report = TargetReport(name, files)
    start = time.perf_counter()
    refuses = target.program.get("restart") == "at_home"
    for (case, accepted, boundary), untrue in zip(expectations, truth, strict=True):
        if case.start == "away" and refuses:
            accepted, untrue = [ExpectedTrace("halt", NOT_AT_HOME)], None
        report.cases += 1
        report.categories[case.category] = report.categories.get(case.category, 0) + 1
        report.boundary += boundary
        runaway = False
        try:
            got = program.run(
                inputs_for(model, target, case.reading, case.vision),
                step_limit=step_limit,
                arm=arm_of(model, name),
                **run_options(model, target, case),
            )
        except StepLimitError as exc:
            problem, pos, rot, runaway = f"run error: {exc}; the remaining cases were not run", [], [], True
        except RunError as exc:
            problem, pos, rot = f"run error: {exc}", [], []
        else:
            problem, pos, rot = None, [], []
            for expected in accepted:
                problem, pos, rot = compare(model, target, case.reading, expected, got, emitter)
                if problem is None:
                    report.halts += got.halted
                    if not got.halted:
                        kind = _kind_of_case(model, case.reading)
                        kind.add_stats(report.kind_stats[kind.name], case.reading, _log_numbers(got.messages))
                    break
        if problem is None and untrue is not None:
            problem = untrue
        report.pos_errors.extend(pos)
        report.rot_errors.extend(rot)
        report.moves += len(pos) if problem is None else 0
        if problem is None:
            report.arm.add(model, name, got.moves)
        if problem is not None:
            report.mismatches += 1
            if len(report.first_mismatches) < 10:
                report.first_mismatches.append(f"{case.category} {describe_case(model, case.reading)}: {problem}")
        if progress is not None:
            progress(1)
        if runaway:
            break
    report.seconds = time.perf_counter() - start
    return report


def output_problem(cell, target, expected, got, before: int) -> str | None:
    """The work pose's output in a run against the cell: set once, to the value, after the move to the
    work pose (before: the moves ahead of the station's, a home move) with the arm standing still;
    not at all where the station stopped before its work pose. None: as it should be."""
    io = cell.io
    if io is None or not target.program.get("signals"):
        return None
    want = []  # (value, after how many moves, where)
    if expected.reason != NOT_AT_HOME:  # released at home before the vision PC is asked
        want.append((not io.value, before, "at home, released"))
    station = expected.station
    if station is not None and len(expected.moves) >= len(station.poses):
        want.append((io.value, before + len(station.poses), "at the work pose"))
    name = signals.signal_name(target, "output", io.output[target.name])
    events = [e for e in got.outputs if e.name == name]
    if len(events) != len(want):
        return f"output {name} set {len(events)} times, expected {len(want)}: {', '.join(w[2] for w in want) or 'none'}"
    for event, (value, after, what) in zip(events, want, strict=True):
        if event.value != value or event.after_moves != after:
            return (
                f"output {name} (line {event.line}) set to {event.value} after move {event.after_moves}, expected "
                f"{value} after move {after} ({what})"
            )
        if event.moving:
            return f"output {name} (line {event.line}) set while the arm moves: it must wait until the arm stands"
    return None
