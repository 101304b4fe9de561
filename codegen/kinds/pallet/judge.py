"""A pallet case's run judged against the float64 reference: moves, payload, outputs, counters, sweep, questions."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from codegen.controllers import get_target
from codegen.emit import Emitter
from codegen.kinds.pallet.cycle import ExpectedMove
from codegen.kinds.pallet.exchange import SHIFT_ENDS, PalletExchange
from codegen.kinds.pallet.kind import KIND
from codegen.kinds.pallet.latch import CounterLatch
from codegen.kinds.pallet.messages import known_question, message_limit, released_question, select_message
from codegen.kinds.pallet.plan import configurations
from codegen.kinds.pallet.program import carried_load, holds_name, known_name, other_flags
from codegen.kinds.pallet.reach import joints_of
from codegen.kinds.pallet.reload import declared_outside_store, reload_proof, store_not_kept, taught_outside_store
from codegen.kinds.pallet.restart import expected
from codegen.kinds.pallet.section import pallets_of
from codegen.kinds.pallet.setup import kept_names, start_joints
from codegen.kinds.pallet.shape import pallet_shape
from codegen.kinds.pallet.sweep import EMPTY_GRIPPER_MM, sweeps
from codegen.kinds.pallet.way_home import joint_percent, way_home, way_joints
from codegen.model.io import signal_name
from codegen.reference import home_move
from codegen.robot.taught import ReachError
from codegen.verify.plan import TOOL_LOAD, Case, Expectation, Judgement, PlannedMove, PlannedOutput, Stored

# the handshake outputs (codegen/kinds/pallet/interlocks.py HANDSHAKES) as the report names them
HANDSHAKE_WHAT = {
    "q_zone": "the arm in Q's zone",
    "q_done": "the pick (place) at Q done",
    "sheet_zone": "the arm in the sheet dispenser's zone",
    "sheet_taken": "a sheet taken from the dispenser",
}


def judge(cell, source, case: Case, trace, setup=None) -> Judgement:
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
        start = start_joints(cell, run.pallet, target.name, case)
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
    for name in other_flags(cell, target, run.pallet):  # a grip of this program clears the task's other flags
        what = "another pallet's flag, cleared by this program's grip"
        stored += (Stored(name, pallet_case.stale and not want.gripped, 0.0, what, pallet_case.stale),)
    boxes = sum(1 for m in want.moves if m.name.endswith("target") and " box " in m.name)
    expectation = Expectation(message, tuple(moves), tuple(outputs), stored, planned_joints=planned_joints)
    reloaded = case.category == "counters_reloaded"
    problem = declared_outside_store(source, target, (layer_name, box_name)) if reloaded else None
    problem = problem or (store_not_kept(source, target) if reloaded else None)
    problem = problem or (taught_outside_store(source, target) if reloaded else None)
    problem = problem or sweeps(pallet_shape(cell, pallet), *_swept(cell, pallet, target.name, want.moves))
    problem = problem or _unsaid(target, want.said, trace)
    problem = problem or _swaps(want, trace, setup, len(moves) - len(want.moves))
    problem = problem or _latched(setup)
    problem = problem or (_unasked(cell, pallet, target, trace) if want.asked else None)
    problem = problem or (_unasked(cell, pallet, target, trace, known_question) if want.known_asked else None)
    return Judgement([expectation], figures=boxes, problem=problem)


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


def _swaps(want, trace, setup, before: int) -> str | None:
    """A done pallet where the PLC resets the counters: the program waits above Q for each swap (the swap comes with
    the arm standing there, after the moves the reference commands before it), and the run ends with it waiting."""
    device = next((d for d in getattr(setup, "devices", ()) if isinstance(d, PalletExchange)), None)
    if device is None:
        return None
    waited = trace.ended == SHIFT_ENDS
    if want.waits and not waited:
        return "the program did not wait above Q for the done pallet's swap (the PLC's reset)"
    if waited and not want.waits:
        return "the program waited for a pallet swap where it should " + ("stop" if want.halt else "end")
    came = [(swap.moves - before, swap.moving) for swap in device.log]
    wanted = [(moves, False) for moves in want.exchanged]
    if came != wanted:
        return (
            f"the pallet swaps came after moves {[m for m, _ in came]} (arm moving: {[v for _, v in came]}), "
            f"expected after {list(want.exchanged)} with the arm standing above Q"
        )
    return None


def _unsaid(target, said: tuple[str, ...], trace) -> str | None:
    """A wait on the supply that lasted the timeout is told to the operator (the program then waits on)."""
    for message in said:
        text = Emitter(target).string(message)
        if text not in getattr(trace, "messages", ()):
            return f"no notification {text!r}: a wait on the supply that lasted the timeout must say so, then wait on"
    return None


def _unasked(cell, pallet, target, trace, question=released_question) -> str | None:
    """The operator is asked what only the operator can tell: after a stop during a release with the gripper empty,
    whether the item is down; after the counters' store came back from its file, whether the pallet is new."""
    text = Emitter(target).string(question(pallet, message_limit(cell)))
    if text not in getattr(trace, "messages", ()):
        return f"the operator was not asked {text!r}: only the operator can tell"
    return None


def _latched(setup) -> str | None:
    """The PLC's retentive memory at the end holds the counters the program last wrote into its registers: the block
    copies them only at the program's "counters written" toggle (codegen/kinds/pallet/latch.py). Whether those
    counters are the reference's is the registers' own check (the expectation's stored counters): a program that
    reports wrong counters, and flips the toggle after each report, fails there, not here."""
    for device in () if setup is None else setup.devices:
        if isinstance(device, CounterLatch) and device.memory != device.reported:
            return (
                f"the PLC's memory holds layer {device.memory[0]}, box {device.memory[1]} when the program ends, "
                f"but the program last wrote layer {device.reported[0]}, box {device.reported[1]}: the PLC copies "
                f"{device.layer} and {device.box} only when the program flips {device.written} after writing them"
            )
    return None
