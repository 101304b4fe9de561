"""The station program's runs judged: each reference trace as the plan every run is checked against (the
home move, the station's moves, the way home, the gripper's outputs, the log), the sweep of unknown ids, figures."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from codegen import protocol
from codegen.controllers import get_target
from codegen.dialects.core.values import RunError, StepLimitError
from codegen.emit import Emitter
from codegen.guard import NOT_AT_HOME, UNKNOWN_STATION_TEXT
from codegen.kinds.station.cases import (
    Case,
    UnknownStation,
    _mode_of_case,
    _truth_problem,
    accepted_traces,
    build_cases,
    describe_case,
    edge_cell,
    edge_only_cell,
    expected_message,
    held_at_start,
    inputs_for,
    run_options,
)
from codegen.kinds.station.joints import expected_joints
from codegen.kinds.station.keys import GRIP, STATION_ID_MAX
from codegen.kinds.station.mode import modes
from codegen.kinds.station.part import held_part, part_load, part_problem
from codegen.kinds.station.section import stations_of
from codegen.model import io as signals
from codegen.reference import ExpectedTrace, home_move
from codegen.robot.expect import arm_of
from codegen.verify import bulk
from codegen.verify.checks import TOLERANCES, log_numbers
from codegen.verify.plan import TOOL_LOAD, Expectation, Judgement, PlannedMove, PlannedOutput, Setup, refuses_start


def setup(cell, target_name: str, case) -> Setup:
    target = get_target(target_name)
    options = run_options(cell, target, case)
    return Setup(
        inputs_for(cell, target, case.reading, case.vision),
        options["devices"],
        options.get("signals", {}),
        options["start_joints"],
    )


def judge(cell, target_name: str, case, trace) -> Judgement:
    """The reference traces a correct program may produce in the case, as plans of the same moves the run has."""
    target = get_target(target_name)
    accepted, boundary = accepted_traces(cell, case, target)
    truth = _truth_problem(cell, case, accepted[0])
    if refuses_start(cell, target, case, allowed=("home", "retreat")) is not None:
        accepted, truth = [ExpectedTrace("halt", NOT_AT_HOME)], None
    emitter = Emitter(target)
    held = held_at_start(cell, case)
    plans = [_plan(cell, target, case.reading, t, trace, emitter, held) for t in accepted]
    figures = None
    mode = _mode_of_case(cell, case.reading)
    if mode is not None and not trace.halted and mode.figures is not None:  # a completed station's figures
        figures = (mode.name, case.reading, log_numbers(trace.messages, log_prefixes()))
    # the part is followed along a run that makes the planned number of moves (other moves: the plan names them); a
    # run that met the plan and mishandles it fails with it (a difference from the plan is named as that, where it is)
    planned = any(len(plan.moves) == len(trace.moves) for plan in plans)
    if truth is None and planned:
        truth = _part(cell, target, accepted, held, trace)
    return Judgement(plans, boundary, figures=figures, truth=truth)


def _part(cell, target, accepted: list[ExpectedTrace], held: bool, trace) -> str | None:
    """Where the run drops the part, or closes the gripper where none is (codegen/kinds/station/part.py), against
    the poses of each trace a correct program may produce: a problem when it has one against every one."""
    if cell.io is None or not target.program.get("signals"):
        return None
    output = signals.signal_name(target, "output", cell.io.output[target.name])
    tolerance = TOLERANCES[target.numbers][0]
    problems = [part_problem(cell, output, t.station, t.moves, held, trace, tolerance) for t in accepted]
    return None if None in problems else problems[0]


def _plan(cell, target, reading, expected: ExpectedTrace, trace, emitter: Emitter, held: bool) -> Expectation:
    home = home_move(cell, target.name)
    if expected.reason == NOT_AT_HOME:
        home = None  # it stops before its first motion
    moves = list(expected.moves)
    back = home is not None and expected.status == "ok" and cell.motion.return_home
    start, loads, after = _payloads(cell, expected, held)
    planned = [_planned(m, load) for m, load in zip(moves, loads, strict=True)]
    if home is not None:
        planned = [_planned(home[0], start), *planned]
        if back:
            planned.append(_planned(home[0], after))
    halt = expected_message(cell, expected, reading, emitter) if expected.status == "halt" else None
    return Expectation(
        halt,
        tuple(planned),
        _outputs(cell, target, expected, 0 if home is None else 1, held),
        logged=_logged(cell, target, reading, expected),
        planned_joints=lambda: _joints(cell, target.name, expected, moves, trace, home, back),
    )


def _planned(move, payload=TOOL_LOAD) -> PlannedMove:
    return PlannedMove(
        name=move.pose_name,
        kind=move.kind,
        tcp2base=move.tcp2base,
        exact=move.exact,
        speed_mm_s=move.speed_mm_s,
        zone_mm=move.zone_mm,
        joint_percent=move.joint_percent,
        payload=payload,
    )


def _payloads(cell, expected: ExpectedTrace, held: bool) -> tuple[Any, list, Any]:
    """The load in force (codegen.verify.plan.PlannedMove.payload) on the move home, at each of the reference's
    station moves, and after them (the way home): with a part held at the start, the tool's and the part's from the
    start where every station carries parts of one load (part.held_part), else from the station's first move where
    the station expects it (the program sets it once it knows the station); from the move after a confirmed grip to
    the confirmed release the tool's and the station's part's; the tool's alone otherwise."""
    common = held_part(cell, stations_of(cell)) if held else None
    start = TOOL_LOAD if common is None else part_load(cell, common).flat()
    station = expected.station
    own = None if station is None else part_load(cell, station)
    if own is None:
        return start, [start] * len(expected.moves), start
    load = own.flat() if held and station.holds_at_start else start
    out = []
    for i, move in enumerate(expected.moves):
        out.append(load)
        k = i - expected.path_start  # the move's pose in the station's path (photos before it: negative)
        action = station.action(move.pose_name) if 0 <= k < len(station.poses) else None
        if action is not None:
            load = own.flat() if action == GRIP else TOOL_LOAD
    return start, out, load


def _joints(cell, target_name: str, expected: ExpectedTrace, moves: list, trace, home, back: bool) -> list | None:
    """The joints the controller's rule gives each move (home, the station's moves with the configuration the
    program names, home again), from the run's own analytic solutions where its poses match (else not known:
    the pose check names the difference first)."""
    if home is None or arm_of(cell, target_name) is None:
        return None
    count = 1 + len(moves) + back
    if len(trace.moves) != count:
        return None
    out = [home[1]]
    if expected.station is not None and moves:
        solved = [g.solutions for g in trace.moves[1 : 1 + len(moves)]]
        out += expected_joints(cell, target_name, expected.station, tuple(moves), home[1], solved)
    if back:
        out.append(home[1])
    return out  # a NaN: the controller's rule finds no solution there (a mismatch)


def _outputs(cell, target, expected: ExpectedTrace, before: int, held: bool) -> tuple[PlannedOutput, ...]:
    """The gripper's output where a station of the cell acts ([station.gripper]): at home, gripped again on a part
    held at the start, else released (before the vision PC is asked); then at each pose of the station where it
    acts, once the arm stands there; not at all where the program stops before its first motion."""
    io = cell.io
    if io is None or not target.program.get("signals") or not any(s.gripper for s in stations_of(cell)):
        return ()
    name = signals.signal_name(target, "output", io.output[target.name])
    out = []
    if expected.reason != NOT_AT_HOME:
        out.append(PlannedOutput(name, io.value if held else not io.value, before, "at home, as the gripper starts"))
    station = expected.station
    if station is not None:
        for i, move in enumerate(expected.moves):
            k = i - expected.path_start  # the move's pose in the station's path (photos before it: negative)
            action = station.action(move.pose_name) if 0 <= k < len(station.poses) else None
            if action is not None:
                value = (action == GRIP) == io.value
                out.append(PlannedOutput(name, value, before + i + 1, f"{action} at {move.pose_name}"))
    return tuple(out)


def _logged(cell, target, reading, expected: ExpectedTrace) -> tuple | None:
    if expected.status != "ok":
        return None
    names = _mode_of_case(cell, reading).log_names
    decimals = target.program.get("log_decimals")
    tolerance = 0.5 * 10.0**-decimals + 1e-3 if decimals is not None else TOLERANCES[target.numbers][0]
    return tuple((name, float(value), tolerance) for name, value in zip(names, expected.logged, strict=True))


def sweep(cell, target_name: str, program, ids: range, step_limit: int, row, texts: list[str] | None = None) -> None:
    """Every id of `ids` that is not a station must stop with the unknown-station message before any move: an
    extra dispatch branch (a misread barcode that moves the robot) is caught wherever in the barcode range it is.
    Given the program's texts, the ids run are one per class of its checks of the id over the whole barcode range
    and a sample (codegen.verify.bulk says why each stands for its class); else every id runs."""
    known = {s.id for s in stations_of(cell)}
    chosen = None if texts is None else set(bulk.representatives(texts, range(STATION_ID_MAX + 1)))
    target = get_target(target_name)
    text = Emitter(target).string(UNKNOWN_STATION_TEXT)
    arm = arm_of(cell, target_name)
    before = 0 if home_move(cell, target_name) is None else 1  # the home move comes first
    for station_id in ids:
        if station_id in known:
            continue
        row.swept += 1
        if chosen is not None and station_id not in chosen:
            continue
        row.bulk_run += 1
        case = Case("unknown_station", UnknownStation(station_id))
        try:
            inputs, options = inputs_for(cell, target, case.reading), run_options(cell, target, case)
            got = program.run(inputs, step_limit=step_limit, arm=arm, **options)
            problem = None
            if len(got.moves) != before or not got.halted or got.halt_message != f"{text}{station_id}":
                problem = f"{len(got.moves) - before} moves, halt message {got.halt_message!r}"
        except StepLimitError as exc:
            row.mismatch(f"unknown station id {station_id}: {exc}; the sweep stopped")
            break
        except RunError as exc:
            problem = f"run error: {exc}"
        if problem is not None:
            row.mismatch(f"unknown station id {station_id}: {problem}")


def sweeps(workers: int) -> list[range]:
    """The barcode range 0..STATION_ID_MAX in as many pieces as workers (two at least)."""
    step = -(-(STATION_ID_MAX + 1) // max(2, workers))
    return [range(i, min(i + step, STATION_ID_MAX + 1)) for i in range(0, STATION_ID_MAX + 1, step)]


def log_prefixes() -> tuple[str, ...]:
    """The station program's log lines whose numbers verify reads (every mode's)."""
    return tuple(prefix for mode in modes().values() for prefix in mode.log_prefixes)


def _by_mode(mine: dict, theirs: dict) -> dict:
    return {
        name: mine[name] + theirs[name] if name in mine and name in theirs else mine.get(name, theirs.get(name))
        for name in {**mine, **theirs}
    }


@dataclass
class StationFigures(protocol.Figures):
    """Each mode's own figures (codegen.kinds.station.mode.StationMode.figures), by the mode's name."""

    modes: dict = field(default_factory=dict, metadata={"add": _by_mode})

    def count(self, case, judged) -> None:
        name, reading, logged = judged
        if name not in self.modes:
            self.modes[name] = modes()[name].figures()
        self.modes[name].count(reading, logged)

    def as_json(self) -> dict:
        """Each mode's own figures under its name (none counted yet: its empty figures)."""
        return {
            name: (self.modes.get(name) or mode.figures()).as_json()
            for name, mode in modes().items()
            if mode.figures is not None
        }


class VerifyPart(protocol.VerifyPlan):
    """The station program's cases (every mode's, the common scenarios'), judged against each mode's reference, and
    the sweep of the station ids that are no station."""

    report_key = "targets"  # verify's JSON: the station program's rows
    scenarios = {  # codegen.verify.plan.SCENARIOS: every one runs (kinds/station/cases.py SCENARIO_OF)
        "start_away": "",
        "start_mid_cycle": "",
        "gripper_silent": "",
        "gripper_stuck": "",
        "device_late": "",
        "device_silent": "",
        "reading_out_of_range": "",
    }
    figures = StationFigures
    listed = {"*": "*", "unknown_ids_checked": "bulk_runs", "unknown_ids_run": "bulk_ids_run"}

    def models(self, cell) -> list:
        """The cell; without an arm, the cell with an extra station of edge-case poses (the pose conventions'
        edges); with one, the edge poses as a cell of their own without the arm, beside it (no arm need reach
        them). The edge programs count in the station program's row."""
        if not stations_of(cell):
            return []
        if cell.robot is None:
            return [(edge_cell(cell), True)]
        edge = edge_only_cell(cell)
        return [(cell, True)] + ([] if edge is None else [(edge, False)])

    def cases(self, cell, source, count: int, seed: int) -> list:
        return build_cases(cell, count, seed)

    def sweeps(self, cell, source, workers: int) -> list[range]:
        return sweeps(workers) if source.sweep else []

    def sweep(self, cell, source, program, ids: range, step_limit: int, row, every: bool = False) -> None:
        sweep(cell, source.target, program, ids, step_limit, row, None if every else [f.text for f in source.files])

    def setup(self, cell, source, case):
        return setup(cell, source.target, case)

    def judge(self, cell, source, case, trace, setup):
        return judge(cell, source.target, case, trace)

    def log_prefixes(self, cell) -> tuple[str, ...]:
        return log_prefixes()

    def describe(self, cell, case) -> str:
        return describe_case(cell, case.reading)

    def report_lines(self, rows: list) -> list[str]:
        summaries = [self.listed_row(row.summary()) for row in rows]
        out = []
        for mode in modes().values():  # each mode's own figures, as a table of its own
            out.extend(mode.stats_lines(summaries))
        swept = sum(row.swept for row in rows)
        if swept:
            run = sum(row.bulk_run for row in rows)
            out.append(
                f"{swept} other station ids, each shown to stop before moving ({run} run: one per class of the "
                "program's checks of the id, and a sample)"
            )
        return out
