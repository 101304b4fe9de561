"""The laser TCP program's runs judged: its moves by role (the way in through the safe pose, the circles, the tip
search, the way out, the way home after a stop) against the procedure's speeds and blends, the production tool it
writes read where it is stored, the start rule."""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from codegen import protocol
from codegen.controllers import get_target
from codegen.emit import Emitter
from codegen.kinds.laser import confirm
from codegen.kinds.laser import program as lp
from codegen.kinds.laser.budget import FLOAT32_MM, TRUTH_MM, tolerances
from codegen.kinds.laser.kind import KIND
from codegen.kinds.laser.reference import expected
from codegen.kinds.laser.section import laser_of
from codegen.kinds.laser.setup import STOPPING_STARTS, pose_in_s, production_cases, setup, start_joints
from codegen.kinds.laser.verify import (
    LaserCase,
    cases,
    previous_tcp,
    station_for,
)
from codegen.kinds.laser.verify import (
    judge as judge_measures,
)
from codegen.reference import home_move
from codegen.verify.plan import Expectation, Judgement, PlannedMove, Stored

FRAME_SETUP = 1  # the index of the setup program that measures the sensor frame (writer.py)
NEAR_MM = 5 * FLOAT32_MM  # a move ends at one of the procedure's fixed points when this close to it
# The motion settings a routine of the production task must leave as a program starts with them: a routine call
# keeps what the routine set (RAPID resets ConfJ, ConfL to \On only at a program load or a start from main), so
# the production moves after the calibration would run without their configuration check
RESTORED = {"confj": "ConfJ", "confl": "ConfL"}


def judge(cell, target_name: str, case: LaserCase, trace) -> Judgement:
    """What it measured against the exact-edge reference (codegen/kinds/laser/verify.py), its moves against the
    procedure's roles, speeds and blends, the production tool it leaves; started away from home and the station
    above the sensors: a stop before any move."""
    target = get_target(target_name)
    previous = previous_tcp(cell, case)
    if case.without_production_tool:
        return _without_production_tool(cell, target, trace)
    # a run the time limit ended (the program still waits at the operator's question) has not left its settings yet
    problem = None if trace.ended else _settings_left(trace)
    if problem is not None:
        return Judgement([], problem=problem)
    if case.growing:  # the runs disagree: a stop for their spread, nothing written
        if not (trace.halted and (trace.halt_message or "").startswith(Emitter(target).string(lp.SPREAD))):
            said = trace.halt_message if trace.halted else "ran to its end"
            return Judgement([], problem=f"the tool grows between runs: expected the spread's stop, {said!r}")
        moves = _roles(cell, target, case, trace, True)
        if isinstance(moves, str):
            return Judgement([], problem=moves)
        return Judgement([Expectation(trace.halt_message, moves, (), _stored(cell, target, None, 0.0, previous))])
    if confirm.unanswered(target, case):
        problem = confirm.silence_problem(cell, target, trace)
        if problem is not None:
            return Judgement([], problem=problem)
        moves = _roles(cell, target, case, trace, True)
        if isinstance(moves, str):
            return Judgement([], problem=moves)
        return Judgement([Expectation(None, moves, (), _stored(cell, target, None, 0.0, previous))])
    if case.start in STOPPING_STARTS:
        message = Emitter(target).string(lp.START_AWAY)
        stored = _stored(cell, target, None, 0.0, previous)
        in_place = (_in_place(cell, target_name, case),)  # a first joint move run where the arm stands (BCO)
        return Judgement([Expectation(message, (), (), stored), Expectation(message, in_place, (), stored)])
    want = expected(cell, station_for(cell, target, replace(case, noise=0.0)))
    tol = tolerances(cell, target, case.noise)
    problem, worst, truth = judge_measures(cell, target, case, trace, want, tol)
    if problem is not None:
        return Judgement([], problem=problem)
    # the operator's No, or the runs' spread (judged above): the tool unchanged
    written = want.halt is None and not trace.halted and not confirm.refused(target, case)
    if want.halt is None and not trace.halted:
        problem = confirm.problem(cell, target, case, trace, previous, _flat_tcp(target, trace))
        if problem is not None:
            return Judgement([], problem=problem)
    moves = _roles(cell, target, case, trace, want.hits is not None)
    if isinstance(moves, str):
        return Judgement([], problem=moves)
    halt = None if written else trace.halt_message  # the message itself: judged above
    stored = _stored(cell, target, want.tcp if written else None, tol.tcp, previous)
    motion = trace.moves[-1].end_time if written and trace.moves else 0.0
    figures = (case.truth, truth, motion, worst)
    return Judgement([Expectation(halt, moves, (), stored)], figures=figures, errors=([worst], []))


def _settings_left(trace) -> str | None:
    """A configuration check the run switched off and left off when it ended (returned or stopped)."""
    left = getattr(trace, "motion_settings", None) or {}
    for key, shown in RESTORED.items():
        if key in left and not left[key]["on"]:
            return (
                f"the program ends with {shown} \\Off (line {left[key]['line']}): the production moves after it keep it"
            )
    return None


def _flat_tcp(target, trace) -> list[float]:
    """The TCP the program found (its own global, flange frame mm)."""
    value = trace.kept.get(lp.kept_names(target)["tcp"]) or []
    return [float(v) for v in (value.values() if isinstance(value, dict) else value)][:3]


def _without_production_tool(cell, target, trace) -> Judgement:
    """The installation without the production tool: the run ends in the error naming it (the runner hands over
    only such an error) before any move, message or output: the read that stops it is the program's first."""
    name = lp.production_name(cell, target)
    if trace.ended is None or name not in trace.ended:
        return Judgement(
            [],
            problem=f"the installation has no {name}: expected the error that it is not defined, "
            f"the program ran ({len(trace.moves)} moves{', stopped' if trace.halted else ''})",
        )
    if trace.messages:
        return Judgement([], problem=f"the installation has no {name}: messages before the stop: {trace.messages!r}")
    return Judgement([Expectation(None, (), (), ())])


def _in_place(cell, target_name: str, case: LaserCase) -> PlannedMove:
    """A joint move where the arm stands (a target's BCO run before the program reads where the TCP is)."""
    robot = cell.robot
    joints = start_joints(cell, target_name, case)
    pose = robot.arms[target_name].kin.fk(np.asarray(joints)) @ robot.tool.tcp2flange
    return PlannedMove(
        name="the first motion where the arm stands",
        kind="joint",
        tcp2base=pose,
        exact=True,
        joint_percent=cell.motion.joint_speed_percent,
        joints=joints,
    )


def _roles(cell, target, case: LaserCase, trace, found: bool) -> tuple[PlannedMove, ...] | str:
    """Each move's role, from where it ends, and so its speed and blend. Started mid-cycle: the way home after a
    stop first (a joint move where the arm stands, where the program makes one; straight up in S to the safe
    height, the orientation kept; the safe pose: work speed, exact stops). Then home, the safe pose (a joint move,
    blended where the target blends joint moves) and above the start (blended: the way down goes on); a half
    circle at circle_speed (the first may blend into the second by the target's circle_blend_mm); the tip search
    at search_speed; the way out to the safe pose (blended as the way in) and home; every other move at the work
    speed with an exact stop (the program measures or decides there). After both circles and the move to the
    search's top: where the reference finds the tip (found), the two moves down and back up are the search; where
    it finds none, a move down is, the moves back up are not. A half circle after the search begins the next run
    (back above the start between runs: a straight move). The tool in force is the cell's throughout."""
    laser = laser_of(cell)
    sensor2base = laser.sensor_frame.matrix()
    base2sensor = np.linalg.inv(sensor2base)
    mids = [np.array(lp.circle_points(laser, k)["mid"]) for k in (0, 1)]
    above = np.array(lp.circle_points(laser, 0)["above"])  # both circles' (the same point above the beams)
    starts = [np.array(lp.circle_points(laser, k)["start"]) for k in (0, 1)]
    safe = np.array(lp.safe_point(laser))
    blend = float(KIND.facts(target).get("circle_blend_mm", 0.0))
    motion = cell.motion
    zone = motion.zone_mm
    joint_zone = zone if KIND.facts(target)["joint_zone"] else 0.0
    home = home_move(cell, target.name)
    moves = list(trace.moves)
    out: list[PlannedMove] = []
    if case.start != "home":
        first = _in_place(cell, target.name, case)
        here = moves[0].tcp2base if moves and moves[0].kind == "joint" else None
        if here is not None and np.linalg.norm(here[:3, 3] - first.tcp2base[:3, 3]) <= NEAR_MM:
            out.append(first)
        begin = (base2sensor @ first.tcp2base)[:3, 3]
        up = pose_in_s(cell, (begin[0], begin[1], safe[2]), first.tcp2base[:3, :3])
        out.append(
            PlannedMove(
                name="back out along the tool's axis",
                kind="linear",
                tcp2base=up,
                exact=True,
                speed_mm_s=motion.work_speed_mm_s,
            )
        )
        out.append(
            PlannedMove(
                name="to the safe pose",
                kind="linear",
                tcp2base=pose_in_s(cell, safe),
                exact=True,
                speed_mm_s=motion.work_speed_mm_s,
            )
        )
    if home is not None:
        out.append(
            PlannedMove(
                name="home",
                kind="joint",
                tcp2base=home[0].tcp2base,
                exact=True,
                joint_percent=motion.joint_speed_percent,
                joints=home[1],
            )
        )
    out.append(
        PlannedMove(
            name="to the safe pose",
            kind="joint",
            tcp2base=pose_in_s(cell, safe),
            exact=joint_zone == 0.0,
            speed_mm_s=motion.speed_mm_s,
            zone_mm=joint_zone,
            joint_percent=motion.joint_speed_percent,
        )
    )
    out.append(
        PlannedMove(
            name="above the start",
            kind="linear",
            tcp2base=pose_in_s(cell, above),
            exact=zone == 0.0,
            speed_mm_s=motion.work_speed_mm_s,
            zone_mm=zone,
        )
    )
    fixed = len(out)
    if len(moves) < fixed:
        return out[: len(moves)] if trace.halted else f"{len(moves)} moves, expected at least {fixed}"
    circles, half, stage = 0, 0, 0  # stage after the circles: 0 before the top, 1 searching, 2 done
    top_z, searched = 0.0, 0
    for i in range(fixed, len(moves)):
        move = moves[i]
        if move.tcp2base is None:
            return f"move {i + 1} (line {move.line}): its pose is not known"
        point = (base2sensor @ move.tcp2base)[:3, 3]
        on_mid = any(np.linalg.norm(point - m) <= NEAR_MM for m in mids)
        on_start = any(np.linalg.norm(point - s) <= NEAR_MM for s in starts)
        if on_mid or (half == 1 and on_start):  # a half circle: the first ends at mid, the second back at start
            if stage == 2:  # the next run's circles: the measurement again
                circles, stage = 0, 0
            first_half = on_mid
            half = 1 if first_half else 0
            out.append(
                PlannedMove(
                    name=f"half circle {2 - first_half}",
                    kind=move.kind,
                    exact=not first_half or blend == 0.0,
                    speed_mm_s=laser.circle_speed_mm_s,
                    zone_mm=blend if first_half else 0.0,
                )
            )
            circles += not first_half  # the second half closes a circle
            continue
        half = 0
        if move.kind == "joint":  # the way out ends home
            final = home[0].tcp2base if home is not None else None
            planned = PlannedMove(
                name="home",
                kind="joint",
                tcp2base=final,
                exact=True,
                joint_percent=motion.joint_speed_percent,
                joints=home[1] if home is not None else None,
            )
        elif circles == 2 and np.linalg.norm(point - safe) <= NEAR_MM:
            safe_pose = pose_in_s(cell, safe)
            planned = PlannedMove(
                name="to the safe pose",
                kind="linear",
                tcp2base=safe_pose,
                exact=joint_zone == 0.0,
                speed_mm_s=motion.work_speed_mm_s,
                zone_mm=joint_zone,
            )
        elif circles == 2 and stage == 0 and np.linalg.norm(point - above) > NEAR_MM:
            planned = PlannedMove(
                name="to the search's top", kind="linear", exact=True, speed_mm_s=motion.work_speed_mm_s
            )
            stage, top_z, searched = 1, point[2], 0
        elif stage == 1 and ((found and searched < 2) or (not found and point[2] < top_z - NEAR_MM)):
            planned = PlannedMove(name="tip search", kind="linear", exact=True, speed_mm_s=laser.search_speed_mm_s)
            searched += 1
        else:
            stage = 2 if stage == 1 else stage
            planned = PlannedMove(name="a straight move", kind="linear", exact=True, speed_mm_s=motion.work_speed_mm_s)
        out.append(planned)
    return tuple(out)


def _stored(cell, target, tcp, tolerance: float, previous: np.ndarray) -> tuple[Stored, ...]:
    """The production tool as the program leaves it: the TCP found, or where it stopped or refused, the last
    calibration's as it was (X, Y, Z as the target's production tool names them, in its units)."""
    spec = KIND.facts(target)["production_tool"]
    name = lp.production_name(cell, target)
    unit = float(spec["unit_mm"])
    values = previous if tcp is None else np.asarray(tcp)
    what = "the TCP found" if tcp is not None else "the production tool unchanged"
    tol = (max(tolerance, FLOAT32_MM) if tcp is not None else FLOAT32_MM) * unit
    # where the target's program saves the tool's module: the file's value too (what a reset brings back; never saved
    # in the run: the file as the last calibration left it)
    names = [(name, what)]
    saved = lp.saved_name(cell, target)
    if saved is not None:
        names.append((saved, f"{what}, in its module's saved file"))
    return tuple(
        Stored(f"{n}.{field}", float(v) * unit, tol, w, if_unset=float(p) * unit)
        for n, w in names
        for field, v, p in zip(spec["fields"], values, previous, strict=True)
    )


@dataclass
class LaserFigures(protocol.Figures):
    # the largest |TCP found - true TCP| where the truth is held
    truth_max_mm: float = field(default=0.0, metadata={"add": protocol.most})
    # |TCP found - true TCP| with the sensor frame off
    frame_error_mm: float = field(default=0.0, metadata={"add": protocol.most})
    # the program's motion time (the longest case that wrote a TCP)
    motion_s: float = field(default=0.0, metadata={"add": protocol.most})
    # the largest difference from the reference (edges, hits, TCP)
    ref_max_mm: float = field(default=0.0, metadata={"add": protocol.most})

    def count(self, case, judged) -> None:
        held, truth, motion, worst = judged
        if held:
            self.truth_max_mm = max(self.truth_max_mm, truth)
        else:
            self.frame_error_mm = max(self.frame_error_mm, truth)
        self.motion_s = max(self.motion_s, motion)
        self.ref_max_mm = max(self.ref_max_mm, worst)

    def as_json(self) -> dict:
        return {
            "tcp_truth_max_mm": self.truth_max_mm,
            "tcp_with_frame_error_mm": self.frame_error_mm,
            "motion_s": self.motion_s,
            "reference_max_mm": self.ref_max_mm,
        }


class VerifyPart(protocol.VerifyPlan):
    """The calibration's cases (the pin's true TCP, the sensors' faults, the operator's answers), judged against the
    beams' float64 reference and the true TCP."""

    report_key = "lasers"
    scenarios = {
        "start_away": "",  # away from home and from the station: stopped before the arm moves
        "start_mid_cycle": "",  # where a stopped calibration left it (the first circle's start): out, home, again
        "gripper_silent": "the calibration program uses no gripper",
        "gripper_stuck": "the calibration program uses no gripper",
        "device_late": "the sensors switch with the pin's position, seen once per input cycle of the controller",
        "device_silent": "",  # sensors that never switch
        "reading_out_of_range": "",  # a TCP or an axis beyond offset_max_mm of the tool as designed
    }
    figures = LaserFigures
    listed = {  # a row as `codegen verify --json` lists it under "lasers"
        "target": "target",
        "files": "files",
        "cases": "cases",
        "mismatches": "mismatches",
        "pos_max_mm": "reference_max_mm",
        "tcp_truth_max_mm": "tcp_truth_max_mm",
        "tcp_with_frame_error_mm": "tcp_with_frame_error_mm",
        "motion_s": "motion_s",
        "first_mismatches": "first_mismatches",
    }

    def cases(self, cell, source, count: int, seed: int) -> list:
        if source.index == FRAME_SETUP:  # the setup program: judged by its own tests, not by these cases
            return []
        out = cases(cell, seed)
        return out + confirm.cases(get_target(source.target), out[0]) + production_cases(cell, source.target)

    def setup(self, cell, source, case):
        return setup(cell, source.target, case)

    def judge(self, cell, source, case, trace, setup):
        return judge(cell, source.target, case, trace)

    def report_lines(self, rows: list) -> list[str]:
        return report_lines(rows)


def report_lines(rows: list) -> list[str]:
    lines = [f"laser tcp  target  cases  fail  ref max mm  tcp-true max mm  frame err mm  motion s (goal {TRUTH_MM})"]
    for r in rows:
        f = r.figures or LaserFigures()
        lines.append(
            f"{'tcp':10} {r.target:6} {r.cases:6d} {r.mismatches:5d}  {f.ref_max_mm:10.4f}  {f.truth_max_mm:15.4f}"
            f"  {f.frame_error_mm:12.4f}  {f.motion_s:8.1f}"
        )
    return lines
