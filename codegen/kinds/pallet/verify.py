"""Verify pallet programs: each case's setup and the float64 reference's moves, payload, outputs and counters as the
plan; the way home after a stop; the counters where a reload leaves them."""

from __future__ import annotations

import random
from dataclasses import dataclass, replace

import numpy as np

from codegen import protocol
from codegen.controllers import get_target
from codegen.emit import Emitter
from codegen.kinds.pallet.analysis import frame_matrix
from codegen.kinds.pallet.cycle import (
    NO,
    YES,
    ExpectedMove,
    PalletCase,
    done_counters,
    expected,
    items,
    start_counters,
)
from codegen.kinds.pallet.interlocks import WAITS_ON
from codegen.kinds.pallet.kind import KIND
from codegen.kinds.pallet.messages import (
    known_question,
    message_limit,
    released_question,
    select_message,
    still_waiting_message,
)
from codegen.kinds.pallet.program import carried_load, counter_names, counter_registers, holds_name, known_name
from codegen.kinds.pallet.reach import configurations, joints_of
from codegen.kinds.pallet.reload import declared_outside_store, reload_proof, store_not_kept
from codegen.kinds.pallet.section import pallets_of
from codegen.kinds.pallet.station import BoxLost, PalletTaken, ResetAnswered, ResetWhileAsked, SupplyLate
from codegen.kinds.pallet.sweep import EMPTY_GRIPPER_MM, sweeps
from codegen.kinds.pallet.way_home import joint_percent, way_home, way_joints
from codegen.kinds.pallet.writer import FORMS_PER_PALLET
from codegen.model.io import LATE_SHARE, signal_name
from codegen.reference import home_move
from codegen.robot.expect import tool_inputs
from codegen.robot.taught import ReachError
from codegen.sim.gripper import Gripper
from codegen.sim.operator import Operator
from codegen.verify.plan import (
    START_AWAY_DEG,
    TOOL_LOAD,
    Case,
    Expectation,
    Judgement,
    PlannedMove,
    PlannedOutput,
    Setup,
    Stored,
)

# A pallet case's category -> the scenario it runs (codegen.verify.plan.SCENARIOS, or the kind's own: a box or a
# sheet that never comes, the pallet not in place, the pallet taken away after the pick, the counters as a reload
# leaves them)
SCENARIO_OF = {
    "gripper_silent": "gripper_silent",
    "gripper_stuck_at_target": "gripper_stuck",
    "gripper_stuck_at_q": "gripper_stuck",
    "gripper_late": "device_late",
    "bad_counters": "reading_out_of_range",
    "start_away": "start_away",
    "start_mid_cycle": "start_mid_cycle",
    "part_missing": "part_missing",
    "place_not_clear": "part_missing",
    "sheet_missing": "part_missing",
    "pallet_absent": "pallet_absent",
    "pallet_taken": "pallet_taken",
    "counters_reloaded": "counters_reloaded",
}
SCENARIOS = {
    "start_away": "",  # the way home: back along the tool's z, above the pallet, home
    "start_mid_cycle": "",  # at a box's target, as a stop leaves the arm: the way home, then the next box
    "gripper_silent": "",
    "gripper_stuck": "",
    "device_late": "",  # the gripper confirms late, within its timeout
    "device_silent": "its one device is the gripper: gripper_silent and gripper_stuck are its silences",
    "reading_out_of_range": "",  # the counters the cell PLC or the operator set, out of the stack
}
MISSING = {"part_missing": "part_present", "place_not_clear": "place_clear", "sheet_missing": "sheet_ready"}


@dataclass(frozen=True)
class PalletRun:
    """One case of a program: which of the cell's pallets it works (a task runs several) and the reference's case."""

    pallet: int
    case: PalletCase


def pallet_indices(cell, source) -> list[int]:
    """The pallets a program works: every one where the target runs them in one task, else the plan's."""
    if KIND.facts(get_target(source.target)).get("task"):
        return list(range(len(pallets_of(cell))))
    return [source.index // FORMS_PER_PALLET]


def own_cases(pallet, rng) -> list[PalletCase]:
    """The whole pallet from its first item; restarts at random items and at the last (the counters preset, as a
    restart finds them), at a slip sheet; a full (empty) pallet, reset by the PLC or not, the reset ignored on a
    pallet not done; counters out of range; the gripper never closing or never opening; an interlock input that
    never comes on; the pallet taken away after the pick; the counters mid-pallet in their store after a reload of
    the program."""
    todo = items(pallet)
    keys = [item.key for item in todo]
    first, done = start_counters(pallet), done_counters(pallet)
    stack = pallet.mode == "stack"
    out = [PalletCase("full_stack" if stack else "full_unstack", *first)]
    out += [PalletCase("restart", *keys[rng.randrange(len(keys))]) for _ in range(3)]
    out.append(PalletCase("restart", *keys[-1]))
    out += [PalletCase("restart", *key) for key in keys if key[1] == 0][:1]  # a slip sheet next
    out.append(PalletCase("pallet_full" if stack else "pallet_empty", *done))
    if pallet.io.reset:
        out.append(PalletCase("pallet_changed", *done, reset=True))
        # the PLC keeps its reset on after the program's answer (a level input, not a request): no new pallet
        out.append(PalletCase("reset_held", *done, reset=True, reset_held=True))
        out.append(PalletCase("reset_ignored", *keys[len(keys) // 2], reset=True))
    counts = {}
    for layer, number in keys:
        counts[layer] = max(counts.get(layer, 0), number)
    bad = [(0, 1), (1, counts[1] + 1), (pallet.layers + 1, 2), (2, 0) if (2, 0) not in keys else (1, 0)]
    out += [PalletCase("bad_counters", *key) for key in bad if key not in keys and key != done]
    out += [PalletCase("gripper_silent", *first, "silent"), PalletCase("held_at_start", *first, closed=True)]
    # a box held at the start (a stop on the way): stacking, the box the counters name (a sheet, where one is next);
    # unstacking, the box gripped before the counters' (the last one: the counters say empty)
    out.append(PalletCase("held_at_start", *keys[len(keys) // 2], closed=True))
    out += [PalletCase("held_at_start", *key, closed=True) for key in keys if key[1] == 0][:1]
    if not stack:
        out.append(PalletCase("held_at_start", *done, closed=True))
    sheets = [key for key in keys if key[1] == 0]  # slip sheets (stacking only)
    if stack:  # it never lets the box go at the target: the counters must stay at that box
        last_of_2 = max(key for key in keys if key[0] == min(2, pallet.layers))
        out.append(PalletCase("gripper_stuck_at_target", *last_of_2, "stuck"))
        out.append(PalletCase("part_missing", *first, missing="part_present"))
        out.append(PalletCase("box_lost", *first, lost=True))  # not counted as placed
        if sheets:
            out.append(PalletCase("sheet_missing", *sheets[0], missing="sheet_ready"))
    else:
        out.append(PalletCase("gripper_stuck_at_q", *first, "stuck"))
        out.append(PalletCase("place_not_clear", *first, missing="place_clear"))
        out.append(PalletCase("box_lost", *first, lost=True))  # dropped in the retreat: not counted as taken
    out.append(PalletCase("pallet_absent", *keys[min(2, len(keys) - 1)], missing="pallet_present"))
    # the pallet taken away once the gripper closed (at Q: the arm must not carry the box, or a sheet, over its place)
    out.append(PalletCase("pallet_taken", *first, taken=True))
    if sheets:
        out.append(PalletCase("pallet_taken", *sheets[0], taken=True))
    out.append(PalletCase("counters_reloaded", *keys[len(keys) // 3]))
    return out


def verify_cases(cell, source, seed: int) -> list[Case]:
    """Each pallet's cases and the common ones made from its first: the gripper late within its timeout, the arm away
    from home, the arm where a stopped cycle left it (at a box's target); a task with several pallets: none selected."""
    out = []
    for index in pallet_indices(cell, source):
        pallet = pallets_of(cell)[index]
        own = own_cases(pallet, random.Random(seed + index)) + _release_cases(pallet, get_target(source.target))
        if holds_name(cell, get_target(source.target), index) is not None:  # the program can tell whose item it is
            own.append(PalletCase("held_by_another", *start_counters(pallet), closed=True, foreign=True))
        if known_name(cell, get_target(source.target), index) is not None:  # the store loaded again from its file
            own += _reloaded_store_cases(pallet)
        if _other_flags(cell, get_target(source.target), index):  # another pallet's flag left set, then a grip
            own.append(PalletCase("stale_flag", *start_counters(pallet), stale=True))
        first = own[0]
        own += [
            replace(first, category="gripper_late", gripper="late"),
            replace(first, category="start_away"),
            replace(first, category="start_mid_cycle"),
        ]
        out += [Case(c.category, PalletRun(index, c), SCENARIO_OF.get(c.category, c.category), _start(c)) for c in own]
    if len(pallet_indices(cell, source)) > 1:  # the task's main: no pallet selected
        first = out[0].data
        out.append(Case("none_selected", PalletRun(-1, first.case), "none_selected"))
    return out


def _reloaded_store_cases(pallet) -> list[PalletCase]:
    """The counters' store loaded again from its file (as a reset of RAPID does) while the pallet is part-built: the
    counters are the file's (a new pallet's), its known flag FALSE. The operator does not answer, or says No: the
    stop before any move; Yes, or the PLC's reset handshake: the pallet's first item next (shown up to the wait for
    the pallet, which is not in place yet, so the run stays short); a reset the PLC keeps on: the stop."""
    first = start_counters(pallet)
    out = [
        PalletCase("store_reloaded", *first, unknown=True),
        PalletCase("store_reloaded", *first, unknown=True, answer=NO),
        PalletCase("store_reloaded", *first, unknown=True, answer=YES, missing="pallet_present"),
    ]
    if pallet.io.reset:
        out.append(PalletCase("store_reloaded", *first, unknown=True, reset=True, missing="pallet_present"))
        out.append(PalletCase("store_reloaded", *first, unknown=True, reset=True, reset_held=True))
        # the PLC's reset while the question is shown (nobody answers): its handshake starts the pallet
        out.append(PalletCase("store_reloaded", *first, unknown=True, reset_asked=True, missing="pallet_present"))
    return out


def _release_cases(pallet, target) -> list[PalletCase]:
    """Stacking, a stop during a release; unstacking, a stop between the grip and Q (the counters marked, the layer
    negative): with the gripper empty the operator says whether the item is down (unstacking: back in its place on
    the pallet) and the counters move on (also past the last box) or stay, or a program that cannot ask stops with a
    message; with the item still held it is finished (unstacking: put down at Q, the counters past it)."""
    keys = [item.key for item in items(pallet)]
    mid, last = keys[len(keys) // 2], keys[-1]
    name = "stopped_in_release" if pallet.mode == "stack" else "stopped_on_the_way"
    # unstacking, the answer that moves the counters past the box is No (the box is not back in its place)
    on = YES if pallet.mode == "stack" else NO
    out = [PalletCase(name, -mid[0], mid[1], closed=True)]
    if pallet.mode == "unstack":  # the last box held: put down at Q, the pallet empty after it
        out.append(PalletCase(name, -last[0], last[1], closed=True))
    if not KIND.facts(target).get("asks"):
        return [*out, PalletCase(name, -mid[0], mid[1])]
    # a question the operator leaves unanswered: where the program asks within a time, its stop, the mark kept
    unanswered = [PalletCase(name, -mid[0], mid[1])] if KIND.facts(target).get("asks_within_s") else []
    return [
        *out,
        *unanswered,
        PalletCase(name, -mid[0], mid[1], answer=YES),
        PalletCase(name, -mid[0], mid[1], answer=NO),
        PalletCase(name, -last[0], last[1], answer=on),
    ]


def _start(case: PalletCase) -> str:
    return {"start_away": "away", "start_mid_cycle": "mid_cycle"}.get(case.category, "home")


def _signals(cell, target, pallet, case: PalletCase, select: int | None, all_pallets) -> dict:
    """The inputs at the start: the gripper's feedback, each interlock on (but the one a case leaves off), the PLC's
    reset, the select inputs of a task (this pallet's on)."""
    out = {signal_name(target, "input", cell.io.feedback[target.name]): case.closed}
    for name, signals in pallet.io.inputs().items():
        out[signal_name(target, "input", signals[target.name])] = name != case.missing
    if target.name in pallet.io.reset:
        out[signal_name(target, "input", pallet.io.reset[target.name])] = case.reset
    for i, other in enumerate(all_pallets):
        if target.name in other.io.select:
            out[signal_name(target, "input", other.io.select[target.name])] = i == select
    return out


def setup(cell, source, case: Case) -> Setup:
    target, run = get_target(source.target), case.data
    index = max(run.pallet, 0)
    pallet = pallets_of(cell)[index]
    layer_name, box_name = counter_names(cell, target, index)
    output = signal_name(target, "output", cell.io.output[target.name])
    feedback = signal_name(target, "input", cell.io.feedback[target.name])
    late = LATE_SHARE * cell.io.timeout_s
    gripper = Gripper(output, feedback, cell.io.value, run.case.gripper, late)
    devices = (gripper,)
    if run.case.taken:  # the pallet taken away once the gripper closes
        present = signal_name(target, "input", pallet.io.pallet_present[target.name])
        devices += (PalletTaken(output, cell.io.value, present),)
    reset_on = run.case.reset or run.case.reset_asked
    if reset_on and not run.case.reset_held and target.name in pallet.io.reset:  # the PLC answers the handshake
        reset = signal_name(target, "input", pallet.io.reset[target.name])
        devices += (ResetAnswered(reset, signal_name(target, "output", pallet.io.done[target.name])),)
    if run.case.reset_asked and target.name in pallet.io.reset:  # the reset comes while the operator is asked
        question = Emitter(target).string(known_question(pallet, message_limit(cell)))
        devices += (ResetWhileAsked(signal_name(target, "input", pallet.io.reset[target.name]), question),)
    if run.case.missing in WAITS_ON:  # the supply comes once the program said it waits on
        signal = signal_name(target, "input", getattr(pallet.io, run.case.missing)[target.name])
        message = Emitter(target).string(still_waiting_message(pallet, run.case.missing, message_limit(cell)))
        devices += (SupplyLate(signal, message),)
    if run.case.lost:  # the box slips out of the gripper on its way
        devices += (BoxLost(output, cell.io.value, feedback),)
    # the operator at the pendant: answers the question (after a stop in a release, or the store reloaded) as the case
    # says, or looks away (a dialog stays shown until the program's own timeout ends it)
    devices += (Operator([] if run.case.answer is None else [run.case.answer], then_silent=True),)
    select = None if run.pallet < 0 else run.pallet
    counters = {layer_name: run.case.layer, box_name: run.case.box}
    holds = holds_name(cell, target, index)
    if holds is not None:  # its store's flag: this program gripped what the gripper holds
        counters[holds] = run.case.closed and not run.case.foreign
    others = _other_flags(cell, target, index)
    for name in others:  # the other pallets' flags of one task: left set where the case says so
        counters[name] = run.case.stale
    known = known_name(cell, target, index)
    if known is not None:  # the counters describe the pallet (set by an earlier reset or the operator)
        counters[known] = True
    if case.category == "counters_reloaded" and not reload_proof(target):
        counters = {}  # a reload cleared the program's own variables: they hold what their declaration gives
    if run.case.unknown:
        counters = {}  # the store loaded again from its file: every value in it is its declaration's
    return Setup(
        {**counters, **tool_inputs(cell, target.name)},
        devices,
        _signals(cell, target, pallet, run.case, select, pallets_of(cell)),
        _start_joints(cell, index, source.target, case),
        (*kept_names(cell, target, index), *([] if holds is None else [holds]), *others, *([known] if known else [])),
    )


def _start_joints(cell, index: int, target_name: str, case: Case):
    home = home_move(cell, target_name)
    if home is None:
        return None
    if case.start == "away":
        return home[1] + np.array(START_AWAY_DEG)
    if case.start == "mid_cycle":  # where a stopped cycle leaves the arm: at its first box's target, released
        pallet = pallets_of(cell)[index]
        want = expected(cell, pallet, case.data.case)
        target_move = next(i for i, m in enumerate(want.moves) if m.name.endswith("target"))
        named = configurations(cell, pallet, target_name)
        return joints_of(cell, target_name, want.moves, "restart", pallet, named)[target_move]
    return np.asarray(cell.robot.home[target_name], dtype=float)


def kept_names(cell, target, index: int) -> tuple[str, str]:
    """Where the run leaves the counters: their store, or the outputs the program reports them in (the
    [program.pallet] table's `kept`)."""
    names = KIND.facts(target).get("kept")
    if names is None:
        return counter_names(cell, target, index)
    registers = counter_registers(cell, target, index)
    return names["layer"].format(layer=registers[0]), names["box"].format(box=registers[1])


def judge(cell, source, case: Case, trace) -> Judgement:
    """The reference's moves (with an arm: the way home from where the arm starts, then home), the payload at each,
    the gripper's outputs and the counters at the end; after a reload, the counters in their store alone."""
    target, run = get_target(source.target), case.data
    if run.pallet < 0:  # a task whose select inputs are all off: it stops before any move
        return Judgement([Expectation(Emitter(target).string(select_message()), (), ())])
    pallet = pallets_of(cell)[run.pallet]
    pallet_case = run.case
    if case.category == "counters_reloaded" and not reload_proof(target):
        pallet_case = replace(pallet_case, layer=0, box=0)  # declared without a value: 0 after the reload
    want = expected(cell, pallet, pallet_case)
    layer_name, box_name = kept_names(cell, target, run.pallet)
    output = signal_name(target, "output", cell.io.output[target.name])
    carried = carried_load(cell, pallet)
    load = None if carried is None else carried.flat()
    zone = pallet.zone_mm
    joint_blend = KIND.facts(target).get("joint_blend", True)
    input_stops = KIND.facts(target).get("input_stops", False)

    def planned(m) -> PlannedMove:
        exact = m.exact or (m.kind == "joint" and not joint_blend) or (m.checked and input_stops) or zone == 0
        payload = load if m.carrying and load is not None else TOOL_LOAD
        return PlannedMove(
            name=m.name,
            kind=m.kind,
            tcp2base=m.tcp2base,
            exact=exact,
            speed_mm_s=m.speed_mm_s,
            zone_mm=0.0 if exact else zone,
            joint_percent=joint_percent(cell, m),
            payload=payload,
        )

    moves = [planned(m) for m in want.moves]
    names = {"gripper": output}
    if target.name in pallet.io.done:  # the PLC's full (empty) output
        names["done"] = signal_name(target, "output", pallet.io.done[target.name])
    what = {"gripper": "gripper", "done": "the pallet's done output (full or empty)", **HANDSHAKE_WHAT}
    for key in HANDSHAKE_WHAT:  # the handshakes at Q and at the sheet dispenser, where the cell gives them
        if target.name in getattr(pallet.io, key):
            names[key] = signal_name(target, "output", getattr(pallet.io, key)[target.name])
    outputs = [PlannedOutput(names[w], value, after, what[w]) for w, value, after in want.outputs if w in names]
    home = home_move(cell, target.name)
    planned_joints = None
    if home is not None and (want.moves or any(w == "gripper" for w, _, _ in want.outputs)):  # home first
        start = _start_joints(cell, run.pallet, target.name, case)
        way = way_home(cell, pallet, target, home, start, want.start[0])
        if pallet_case.closed and (pallet.mode == "unstack" or want.start[1] != 0) and load is not None:
            way = [replace(m, payload=load) for m in way]  # a box held since the start: its payload on the way home
        moves = [*way, *moves]
        # set from the counters and the sensor before the way home (after 0 moves): the done output, the grip on a
        # held item; the rest after it
        before = {(names.get("done"), True), (names.get("done"), False), (output, cell.io.value)}
        outputs = [
            o
            if ((o.name, o.value) in before and o.after_moves == 0)
            else replace(o, after_moves=o.after_moves + len(way))
            for o in outputs
        ]

        def planned_joints() -> list | None:  # by the controller's rule, with the configurations the program names
            try:
                named = configurations(cell, pallet, target.name)
                head = way_joints(cell, pallet, target.name, way[:-1], start, named) if len(way) > 1 else []
                return [*head, home[1], *joints_of(cell, target.name, want.moves, "verify", pallet, named)]
            except ReachError:
                return None

    message = None if want.halt is None else Emitter(target).string(want.halt)
    stored = (
        Stored(layer_name, want.counters[0], 0.0, "the layer counter", pallet_case.layer),
        Stored(box_name, want.counters[1], 0.0, "the box counter", pallet_case.box),
    )
    holds = holds_name(cell, target, run.pallet)
    if holds is not None:
        preset = pallet_case.closed and not pallet_case.foreign
        stored += (Stored(holds, want.holds, 0.0, "the flag: this program gripped what the gripper holds", preset),)
    known = known_name(cell, target, run.pallet)
    if known is not None:
        what = "the flag: the counters describe the pallet (FALSE: the store as its file gives it)"
        stored += (Stored(known, want.known, 0.0, what, not pallet_case.unknown),)
    for name in _other_flags(cell, target, run.pallet):  # a grip of this program clears the task's other flags
        what = "another pallet's flag, cleared by this program's grip"
        stored += (Stored(name, pallet_case.stale and not want.gripped, 0.0, what, pallet_case.stale),)
    boxes = sum(1 for m in want.moves if m.name.endswith("target") and " box " in m.name)
    expectation = Expectation(message, tuple(moves), tuple(outputs), stored, planned_joints=planned_joints)
    reloaded = case.category == "counters_reloaded"
    problem = declared_outside_store(source, target, (layer_name, box_name)) if reloaded else None
    problem = problem or (store_not_kept(source, target) if reloaded else None)
    problem = problem or sweeps(pallet, frame_matrix(pallet), *_swept(cell, pallet, target.name, want.moves))
    problem = problem or _unsaid(target, want.said, trace)
    problem = problem or (_unasked(cell, pallet, target, trace) if want.asked else None)
    problem = problem or (_unasked(cell, pallet, target, trace, known_question) if want.known_asked else None)
    return Judgement([expectation], figures=boxes, problem=problem)


# the handshake outputs (codegen/kinds/pallet/interlocks.py HANDSHAKES) as the report names them
HANDSHAKE_WHAT = {
    "q_zone": "the arm in Q's zone",
    "q_done": "the pick (place) at Q done",
    "sheet_zone": "the arm in the sheet dispenser's zone",
    "sheet_taken": "a sheet taken from the dispenser",
}


def _swept(cell, pallet, target_name: str, moves) -> tuple[list, object, float]:
    """The moves the sweep follows, the arm's forward kinematics (tcp2base) and the empty gripper's width: with an
    arm, from home, each move with the joints the program moves through (a joint move is a straight line in joint
    space); without one, the TCP's straight segments from the first move."""
    home = home_move(cell, target_name)
    if home is None:
        return list(moves), None, EMPTY_GRIPPER_MM
    try:
        named = configurations(cell, pallet, target_name)
        joints = joints_of(cell, target_name, moves, "verify: the sweep", pallet, named)
    except ReachError:
        return list(moves), None, EMPTY_GRIPPER_MM
    arm, tcp2flange = cell.robot.arms[target_name], cell.robot.tool.tcp2flange
    start = ExpectedMove(
        kind="joint",
        tcp2base=home[0].tcp2base,
        name="home",
        speed_mm_s=0.0,
        exact=True,
        joints=np.asarray(home[1], dtype=float),
    )
    out = [start, *(replace(m, joints=q) for m, q in zip(moves, joints, strict=True))]
    return out, (lambda q: arm.kin.fk(q) @ tcp2flange), EMPTY_GRIPPER_MM


def _unsaid(target, said: tuple[str, ...], trace) -> str | None:
    """A wait on the supply that lasted the timeout is told to the operator (the program then waits on)."""
    for message in said:
        text = Emitter(target).string(message)
        if text not in getattr(trace, "messages", ()):
            return f"no notification {text!r}: a wait on the supply that lasted the timeout must say so, then wait on"
    return None


def _other_flags(cell, target, index: int) -> list[str]:
    """Where one task runs every pallet's program: the other pallets' holds flags (this program's grip clears
    them, so a flag left set by an item taken out by hand never makes another pallet's item look like theirs)."""
    if not KIND.facts(target).get("task"):
        return []
    names = [holds_name(cell, target, i) for i in range(len(pallets_of(cell)))]
    return [name for i, name in enumerate(names) if i != index and name is not None]


def _unasked(cell, pallet, target, trace, question=released_question) -> str | None:
    """The operator is asked what only the operator can tell: after a stop during a release with the gripper empty,
    whether the item is down; after the counters' store came back from its file, whether the pallet is new."""
    text = Emitter(target).string(question(pallet, message_limit(cell)))
    if text not in getattr(trace, "messages", ()):
        return f"the operator was not asked {text!r}: only the operator can tell"
    return None


@dataclass
class PalletFigures(protocol.Figures):
    boxes: int = 0  # boxes placed (or taken) over the passing cases

    def count(self, case, judged: int) -> None:
        self.boxes += judged

    def as_json(self) -> dict:
        return {"boxes_placed": self.boxes}


class VerifyPart(protocol.VerifyPlan):
    """A pallet program's cases (a whole stack and its interruptions, each box's pose from the pallet's reference)."""

    report_key = "pallets"
    scenarios = SCENARIOS
    figures = PalletFigures
    listed = {  # a row as `codegen verify --json` lists it under "pallets"
        "target": "target",
        "pallet": "program",
        "files": "files",
        "cases": "cases",
        "mismatches": "mismatches",
        "boxes_placed": "boxes_placed",
        "pos_max_mm": "position_error_mm.max",
        "rot_max_deg": "orientation_error_deg.max",
        "cases_per_s": "cases_per_second",
        "first_mismatches": "first_mismatches",
    }

    def cases(self, cell, source, count: int, seed: int) -> list:
        return verify_cases(cell, source, seed)

    def setup(self, cell, source, case):
        return setup(cell, source, case)

    def judge(self, cell, source, case, trace, setup):
        return judge(cell, source, case, trace)

    def describe(self, cell, case) -> str:
        run = case.data
        pallet = "" if run.pallet < 0 else f"pallet {pallets_of(cell)[run.pallet].name} "
        return f"{pallet}layer {run.case.layer} box {run.case.box}"

    def report_lines(self, rows: list) -> list[str]:
        lines = ["pallet program          target    cases  fail  boxes"]
        for r in rows:
            boxes = 0 if r.figures is None else r.figures.boxes
            lines.append(f"{r.program[:23]:23} {r.target:8} {r.cases:6d} {r.mismatches:5d} {boxes:6d}")
        return lines
