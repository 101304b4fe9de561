"""The station program's cases: each station's readings, the vision PC's and the gripper's behaviours, where the
arm starts, unknown stations; their simulated devices and the reference traces a correct program may produce."""

from __future__ import annotations

import random
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from codegen.controllers import Target, get_target
from codegen.emit import Emitter
from codegen.guard import (
    CONNECTION_LOST,
    NO_ANSWER,
    NO_FEEDBACK,
    NO_PART,
    NOT_AT_HOME,
    NOT_RELEASED,
    PART_HELD,
    UNKNOWN_STATION,
    UNKNOWN_STATION_TEXT,
    halt_message,
)
from codegen.kinds.station.keys import GRIP, RELEASE, STATION_ID_MAX
from codegen.kinds.station.mode import mode_of, modes
from codegen.kinds.station.plan import taught_poses
from codegen.kinds.station.section import Station, section_of, stations_of, with_section
from codegen.model import io as signals
from codegen.model import vision
from codegen.model.cell import Cell, TaughtPose
from codegen.poses import native_values
from codegen.reference import ExpectedTrace, home_move
from codegen.sim.gripper import Gripper
from codegen.sim.vision_pc import VisionPC
from codegen.verify.plan import START_AWAY_DEG, tool_inputs

# A station case's category -> the scenario it runs (codegen.verify.plan.SCENARIOS; the others are the mode's own)
SCENARIO_OF = {
    "start_away": "start_away",
    "start_retreat": "start_mid_cycle",
    "gripper_silent": "gripper_silent",
    "gripper_stuck": "gripper_stuck",
    "vision_late": "device_late",
    "vision_never": "device_silent",
    "invalid_reading": "reading_out_of_range",
    "frame_invalid_pixels": "reading_out_of_range",
}


@dataclass(frozen=True)
class Case:
    """One verify case: a category for the report, the mode's description of the situation and how
    the simulated vision PC answers (codegen.model.vision.BEHAVIOURS)."""

    category: str
    reading: Any  # the mode's case type; has station_id
    vision: str = "prompt"
    gripper: str = "prompt"  # how the simulated gripper answers the work pose's signal (codegen.sim.gripper)
    start: str = "home"  # where the arm stands when the program starts: "home", "away" from it, or "retreat":
    # at its station's taught retreat (where a stopped cycle leaves it)
    # the gripper holds a part when the program starts (None: as the case's station expects, else empty)
    held: bool | None = None

    @property
    def scenario(self) -> str:
        """The common scenario the case runs (codegen.verify.plan.SCENARIOS), or its own category."""
        return SCENARIO_OF.get(self.category, self.category)


@dataclass(frozen=True)
class UnknownStation:
    """A station id the cell does not have: every program must halt with the unknown-station message."""

    station_id: int


def _mode_of_case(cell: Cell, reading):
    if isinstance(reading, UnknownStation):
        return None
    return mode_of(section_of(cell).station_by_id(reading.station_id))


def inputs_for(cell: Cell, target: Target, reading, behaviour: str = "prompt") -> dict:
    """What the controller holds when the program starts: the vision PC's variables from the previous
    cycle (a plausible reading of the station, its request answered), the controller's numbered
    tool and the mode's own values."""
    mode = _mode_of_case(cell, reading)
    tools = tool_inputs(cell, target.name)  # the controller's numbered tool, where the program selects one
    previous, answered = _previous_reading(cell, target, reading), vision.answered(target, behaviour)
    if mode is None:
        return {**previous, **answered, **tools}
    return {**previous, **answered, **mode.inputs(cell, target, reading), **tools}


def start_joints(cell: Cell, target: Target, case: Case):
    """Where the arm stands when the program starts (deg): at home, away from it or at the case's
    station's taught retreat; None without an arm."""
    home = home_move(cell, target.name)
    if home is None:
        return None
    if case.start == "retreat":
        taught, _ = taught_poses(cell, target.name, section_of(cell).station_by_id(case.reading.station_id))
        return next(pose.joints for pose in taught if pose.name == "retreat")
    return home[1] + (np.array(START_AWAY_DEG) if case.start == "away" else 0.0)


def _previous_reading(cell: Cell, target: Target, reading) -> dict:
    """The vision PC's variables from the previous cycle: a reading of the case's station (an unknown
    station's case: of the cell's first station)."""
    station = (
        section_of(cell).station_by_id(reading.station_id) if _mode_of_case(cell, reading) else stations_of(cell)[0]
    )
    return mode_of(station).previous(cell, target, station)


def held_at_start(cell: Cell, case: Case) -> bool:
    """Whether the gripper holds a part when the case starts: the case's own word, else what its station expects
    (a station that puts a part down first starts with one), else empty (the last cycle put its part down)."""
    if case.held is not None:
        return case.held
    if isinstance(case.reading, UnknownStation):
        return False
    station = section_of(cell).station_by_id(case.reading.station_id)
    return bool(station is not None and station.holds_at_start)


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
    its feedback as the gripper starts (on: it holds a part)."""
    options = {"devices": devices_for(cell, target, case), "start_joints": start_joints(cell, target, case)}
    gripper = _gripper_signals(cell, target.name)
    if gripper is not None:
        options["signals"] = {gripper[1]: held_at_start(cell, case)}
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
    mode = _mode_of_case(cell, case.reading)
    if mode is None:
        answer = {target.program["inputs"]["station"]: case.reading.station_id}
        camera = None
    else:
        answer, camera = mode.answer(cell, target, case.reading), mode.camera(cell, case.reading)
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
    stations = stations_of(cell)
    new_id = max(s.id for s in stations) + 1
    mode = next((m for m in modes().values() if m.edge_spec() is not None), None)
    if new_id > STATION_ID_MAX or mode is None:
        return cell
    station = Station(new_id, "verify_edge_poses", poses, mode.name, mode.edge_spec())
    return with_section(cell, stations=(*stations, station))


def edge_only_cell(cell: Cell) -> Cell | None:
    """For a cell with an arm: its edge-case poses (which no arm need reach: they test the pose
    conventions) as a cell of their own without the arm, verified beside the cell's programs."""
    edge = edge_cell(replace(cell, robot=None))
    if cell.robot is None or len(stations_of(edge)) == len(stations_of(cell)):
        return None
    return with_section(edge, stations=stations_of(edge)[-1:])


def build_cases(cell: Cell, count: int, seed: int) -> list[Case]:
    """Each station's cases from its mode (one random sequence for the cell), then its first case again
    with the vision PC late, silent, replaying the last cycle, answering twice, answering another
    request or sending a late answer to the previous cycle first; then unknown stations."""
    rng = random.Random(seed)
    cases: list[Case] = []
    for station in stations_of(cell):
        own = mode_of(station).cases(cell, station, count, rng)
        cases.extend(own)
        cases.extend(Case(f"vision_{b}", own[0].reading, b) for b in vision.BEHAVIOURS[1:] if own)
        if own and station.gripper:  # the gripper never confirms a grip, or never a release; the other start
            cases.append(Case("gripper_silent", own[0].reading, gripper="silent"))
            cases.append(Case("gripper_stuck", own[0].reading, gripper="stuck"))
            cases.append(Case("part_held", own[0].reading, held=not station.holds_at_start))
    if cell.robot is not None and cases:  # the program started with the arm away from home, or at a retreat
        cases.append(Case("start_away", cases[0].reading, start="away"))
        if cell.motion.retreat_mm > 0:
            cases.append(Case("start_retreat", cases[0].reading, start="retreat"))
    known = {s.id for s in stations_of(cell)}
    for station_id in (0, -1, max(known) + 1, STATION_ID_MAX, 99999):
        if station_id not in known:
            cases.append(Case("unknown_station", UnknownStation(station_id)))
    return cases


# --- comparison ------------------------------------------------------------------------------


def _truth_problem(cell: Cell, case: Case, reference: ExpectedTrace) -> str | None:
    mode = _mode_of_case(cell, case.reading)
    if mode is None or case.vision in vision.UNANSWERED:  # the camera's view never reaches the program
        return None
    if reference.reason in (PART_HELD, NO_PART, NO_FEEDBACK, NOT_RELEASED):  # the gripper's stop, not the mode's
        return None
    return mode.truth_problem(cell, case.reading, reference)


def accepted_traces(cell: Cell, case: Case, target: Target | None = None) -> tuple[list[ExpectedTrace], bool]:
    """The traces a correct program may produce for a case (a boundary reading: either side), on `target` (a
    network channel tells a lost connection from a silent vision PC: its own stop)."""
    if case.vision in vision.UNANSWERED:  # the program must not use what it did not get: it halts at home
        lost = target is not None and vision.lost(target, case.vision)
        return [ExpectedTrace("halt", CONNECTION_LOST if lost else NO_ANSWER)], False
    mode = _mode_of_case(cell, case.reading)
    if mode is None:
        return [ExpectedTrace("halt", UNKNOWN_STATION)], False
    accepted, boundary = mode.accepted(cell, case.reading)
    second = mode.second_look(case.reading) if case.vision == "twice" else None
    if second is not None:  # answered twice within one poll: either answer, used whole, is correct
        more, more_boundary = mode.accepted(cell, second)
        accepted, boundary = [*accepted, *more], boundary or more_boundary
    station = section_of(cell).station_by_id(case.reading.station_id)
    if station.holds_at_start is not None and held_at_start(cell, case) != station.holds_at_start:
        # it stops at home before the station (and its guard): the part it holds, or misses, is the operator's
        return [ExpectedTrace("halt", PART_HELD if held_at_start(cell, case) else NO_PART, station)], False
    # the station stops at its first grip (release) with the message when the gripper never confirms it
    stop = {"silent": (GRIP, NO_FEEDBACK), "stuck": (RELEASE, NOT_RELEASED)}.get(case.gripper)
    at = None if stop is None else _first_action(station, stop[0])
    if at is not None:
        accepted = [
            replace(t, status="halt", reason=stop[1], moves=t.moves[: t.path_start + at + 1]) if t.status == "ok" else t
            for t in accepted
        ]
    return accepted, boundary


def _first_action(station: Station, action: str) -> int | None:
    """The index in the station's path of the first pose where the gripper does `action`, None: nowhere."""
    return next((i for i, p in enumerate(station.poses) if station.action(p.name) == action), None)


def expected_message(cell: Cell, trace: ExpectedTrace, reading, emitter: Emitter) -> str:
    if trace.reason == UNKNOWN_STATION:
        return emitter.string(UNKNOWN_STATION_TEXT) + str(reading.station_id)
    if trace.reason in (NO_ANSWER, CONNECTION_LOST, NO_FEEDBACK, NOT_AT_HOME, NOT_RELEASED, PART_HELD, NO_PART):
        return emitter.string(halt_message(cell, trace.reason, None, 0))
    mode = mode_of(trace.station)
    return emitter.string(mode.fitted_message(cell, trace.reason, trace.station, emitter.target.string_max))


def describe_case(cell: Cell, reading) -> str:
    mode = _mode_of_case(cell, reading)
    return f"station {reading.station_id}" if mode is None else mode.describe_reading(reading)
