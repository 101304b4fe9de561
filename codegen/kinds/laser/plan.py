"""The laser TCP program's runs judged: its moves by role (the circles, the tip search, the moves between) against the
procedure's speeds, the tool data it writes for later programs read where it is stored, the restart rule."""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from codegen.controllers import get_target, numbered_names
from codegen.kinds.laser import program as lp
from codegen.kinds.laser.facts import facts
from codegen.kinds.laser.reference import expected
from codegen.kinds.laser.section import laser_of
from codegen.kinds.laser.verify import (
    FLOAT32_MM,
    STEP_LIMIT,
    TRUTH_MM,
    LaserCase,
    station_for,
    tolerances,
)
from codegen.kinds.laser.verify import (
    judge as judge_measures,
)
from codegen.reference import home_move
from codegen.robot import solve
from codegen.robot.expect import tool_inputs
from codegen.verify.plan import START_AWAY_DEG, Expectation, Judgement, PlannedMove, Setup, Stored, refuses_start

NEAR_MM = 5 * FLOAT32_MM  # a move ends at one of the procedure's fixed points when this close to it


def setup(cell, target_name: str, case: LaserCase) -> Setup:
    target = get_target(target_name)
    return Setup(
        tool_inputs(cell, target_name),
        (station_for(cell, target, case),),
        {},
        _start_joints(cell, target_name, case),
        tuple(lp.kept_names(target).values()) + _stored_names(cell, target),
        STEP_LIMIT,
        float(target.program["signal_cycle_s"]),
    )


def _stored_names(cell, target) -> tuple[str, ...]:
    stored = facts(target).get("stored_tool")
    return () if stored is None else (_stored_name(cell, target, stored),)


def _stored_name(cell, target, stored: dict) -> str:
    """Where the program stores the TCP found: the controller's numbered tool the cell names
    ([cell.tool] numbered), else the program's own tool data."""
    number = cell.robot.tool.numbered.get(target.name) if cell.robot is not None else None
    return stored["name"] if number is None else numbered_names(target.name, number)[0]


def _start_joints(cell, target_name: str, case: LaserCase):
    robot = cell.robot
    if robot is None or target_name not in robot.arms:
        return None
    home = np.asarray(robot.home[target_name], dtype=float)
    if case.start == "away":
        return home + np.array(START_AWAY_DEG)
    if case.start == "mid_cycle":  # where a stopped calibration leaves the arm: at the first circle's start
        laser = laser_of(cell)
        start = np.array(lp.circle_points(laser, 0)["start"])
        sensor2base = laser.sensor_frame.matrix()
        tcp2base = np.eye(4)
        tcp2base[:3, :3] = sensor2base[:3, :3] @ lp.DOWN @ robot.tool.tcp2flange[:3, :3]
        tcp2base[:3, 3] = sensor2base[:3, :3] @ start + sensor2base[:3, 3]
        arm = robot.arms[target_name]
        joints, _ = solve.nearest(arm, solve.branches(arm, solve.flange_poses(tcp2base, robot.tool.tcp2flange)), home)
        return joints
    return home


def judge(cell, target_name: str, case: LaserCase, trace) -> Judgement:
    """What it measured against the exact-edge reference (codegen/kinds/laser/verify.py), its moves against the
    procedure's roles and speeds, the tool data it stores; a start away or mid-cycle: the restart rule."""
    target = get_target(target_name)
    message = refuses_start(cell, target, case)
    if message is not None:
        return Judgement([Expectation(message, (), (), _stored(cell, target, None, 0.0))])
    want = expected(cell, station_for(cell, target, replace(case, noise=0.0)))
    tol = tolerances(cell, target, case.noise)
    problem, worst, truth = judge_measures(cell, target, case, trace, want, tol)
    if problem is not None:
        return Judgement([], problem=problem)
    written = want.halt is None
    moves = _roles(cell, target, trace, written, want.hits is not None)
    if isinstance(moves, str):
        return Judgement([], problem=moves)
    if written and facts(target).get("stored_tool") is None and moves:  # no tool data: the active TCP holds it
        found = cell.robot.tool.tcp2flange.copy()
        found[:3, 3] = want.tcp
        moves = (*moves[:-1], replace(moves[-1], tool=found, tool_tolerance=tol.tcp + FLOAT32_MM))
    halt = None if written else trace.halt_message  # the message itself: judged above
    stored = _stored(cell, target, want.tcp if written else None, tol.tcp)
    motion = trace.moves[-1].end_time if written and trace.moves else 0.0
    figures = (case.truth, truth, motion, worst)
    return Judgement([Expectation(halt, moves, (), stored)], figures=figures, errors=([worst], []))


def _roles(cell, target, trace, written: bool, found: bool) -> tuple[PlannedMove, ...] | str:
    """Each move's role from where it ends (the procedure's fixed points in S) and so its speed: home and the
    joint moves at the travel speeds, a half circle at circle_speed, the tip search at search_speed, every other
    move at the work speed; each stops exactly (the first half of a circle may blend into the second by the
    target's circle_blend_mm). After both circles and the move to the search's top: where the reference finds
    the tip (found), the two moves down and back up are the search; where it finds none, a move down is, the
    moves back up are not. Once the TCP is written, the tool in force may be the new one (its value is judged
    where it is stored)."""
    laser = laser_of(cell)
    sensor2base = laser.sensor_frame.matrix()
    base2sensor = np.linalg.inv(sensor2base)
    mids = [np.array(lp.circle_points(laser, k)["mid"]) for k in (0, 1)]
    above = np.array(lp.circle_points(laser, 0)["above"])  # both circles' (the same point above the beams)
    starts = [np.array(lp.circle_points(laser, k)["start"]) for k in (0, 1)]
    blend = float(facts(target).get("circle_blend_mm", 0.0))
    motion = cell.motion
    home = home_move(cell, target.name)
    out, circles, half, stage = [], 0, 0, 0  # stage after the circles: 0 before the top, 1 searching, 2 done
    top_z, searched = 0.0, 0
    for i, move in enumerate(trace.moves):
        if i == 0 and home is not None:
            out.append(
                PlannedMove(
                    "home", "joint", home[0].tcp2base, True, None, 0.0, motion.joint_speed_percent, joints=home[1]
                )
            )
            continue
        if move.tcp2base is None:
            return f"move {i + 1} (line {move.line}): its pose is not known"
        point = (base2sensor @ move.tcp2base)[:3, 3]
        on_mid = any(np.linalg.norm(point - m) <= NEAR_MM for m in mids)
        on_start = any(np.linalg.norm(point - s) <= NEAR_MM for s in starts)
        tool = "cell" if not (written and circles == 2) else None
        if on_mid or (half == 1 and on_start):  # a half circle: the first ends at mid, the second back at start
            first = on_mid
            half = 1 if first else 0
            out.append(
                PlannedMove(
                    f"half circle {2 - first}",
                    move.kind,
                    None,
                    not first or blend == 0.0,
                    laser.circle_speed_mm_s,
                    blend if first else 0.0,
                    tool=tool,
                )
            )
            circles += not first  # the second half closes a circle
            continue
        half = 0
        if move.kind == "joint":
            final = i == len(trace.moves) - 1 and home is not None
            speed = None if final else motion.speed_mm_s
            name = "home" if final else "a joint move"
            pose = home[0].tcp2base if final and tool == "cell" else None  # a joint target's pose: with its tool
            planned = PlannedMove(
                name,
                "joint",
                pose,
                True,
                speed,
                0.0,
                motion.joint_speed_percent,
                joints=home[1] if final else None,
                tool=tool,
            )
        elif circles == 2 and stage == 0 and np.linalg.norm(point - above) > NEAR_MM:
            planned = PlannedMove("to the search's top", "linear", None, True, motion.work_speed_mm_s, 0.0, tool=tool)
            stage, top_z, searched = 1, point[2], 0
        elif stage == 1 and ((found and searched < 2) or (not found and point[2] < top_z - NEAR_MM)):
            planned = PlannedMove("tip search", "linear", None, True, laser.search_speed_mm_s, 0.0, tool=tool)
            searched += 1
        else:
            stage = 2 if stage == 1 else stage
            planned = PlannedMove("a straight move", "linear", None, True, motion.work_speed_mm_s, 0.0, tool=tool)
        out.append(planned)
    return tuple(out)


def _stored(cell, target, tcp, tolerance: float) -> tuple[Stored, ...]:
    """The tool data the program leaves for later programs: the TCP found (or, where it stopped or refused, the
    tool's data as it was), read where the target's program stores it (its [program.laser] stored_tool)."""
    stored = facts(target).get("stored_tool")
    if stored is None:
        return ()
    values = cell.robot.tool.tcp2flange[:3, 3] if tcp is None else np.asarray(tcp)
    what = "the TCP found" if tcp is not None else "the tool's data unchanged"
    tol = max(tolerance, FLOAT32_MM) if tcp is not None else FLOAT32_MM
    return tuple(
        Stored(f"{_stored_name(cell, target, stored)}.{field}", float(v), tol, what)
        for field, v in zip(stored["fields"], values, strict=True)
    )


@dataclass
class LaserFigures:
    truth_max_mm: float = 0.0  # the largest |TCP found - true TCP| where the truth is held
    frame_error_mm: float = 0.0  # |TCP found - true TCP| with the sensor frame off
    motion_s: float = 0.0  # the program's motion time (the longest case that wrote a TCP)
    ref_max_mm: float = 0.0  # the largest difference from the reference (edges, hits, TCP)


def add(figures: LaserFigures, judged) -> None:
    held, truth, motion, worst = judged
    if held:
        figures.truth_max_mm = max(figures.truth_max_mm, truth)
    else:
        figures.frame_error_mm = max(figures.frame_error_mm, truth)
    figures.motion_s = max(figures.motion_s, motion)
    figures.ref_max_mm = max(figures.ref_max_mm, worst)


def merge(into: LaserFigures, part: LaserFigures) -> None:
    into.truth_max_mm = max(into.truth_max_mm, part.truth_max_mm)
    into.frame_error_mm = max(into.frame_error_mm, part.frame_error_mm)
    into.motion_s = max(into.motion_s, part.motion_s)
    into.ref_max_mm = max(into.ref_max_mm, part.ref_max_mm)


def legacy_summary(row) -> dict:
    """A row as `codegen verify --json` lists it under "lasers"."""
    f = row.figures or LaserFigures()
    return {
        "target": row.target,
        "files": row.files,
        "cases": row.cases,
        "mismatches": row.mismatches,
        "pos_max_mm": f.ref_max_mm,
        "tcp_truth_max_mm": f.truth_max_mm,
        "tcp_with_frame_error_mm": f.frame_error_mm,
        "motion_s": f.motion_s,
        "first_mismatches": row.first_mismatches,
    }


def report_lines(rows: list) -> list[str]:
    lines = [f"laser tcp  target  cases  fail  ref max mm  tcp-true max mm  frame err mm  motion s (goal {TRUTH_MM})"]
    for r in rows:
        f = r.figures or LaserFigures()
        lines.append(
            f"{'tcp':10} {r.target:6} {r.cases:6d} {r.mismatches:5d}  {f.ref_max_mm:10.4f}  {f.truth_max_mm:15.4f}"
            f"  {f.frame_error_mm:12.4f}  {f.motion_s:8.1f}"
        )
    return lines
