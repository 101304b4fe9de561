"""A pallet case's run set up: counters and flags preset, inputs, simulated devices, where the arm starts."""

from __future__ import annotations

import numpy as np

from codegen.controllers import get_target
from codegen.emit import Emitter
from codegen.kinds.pallet.cycle import PalletCase
from codegen.kinds.pallet.exchange import PalletExchange
from codegen.kinds.pallet.interlocks import WAITS_ON
from codegen.kinds.pallet.kind import KIND
from codegen.kinds.pallet.latch import CounterLatch
from codegen.kinds.pallet.messages import known_question, message_limit, still_waiting_message
from codegen.kinds.pallet.plan import configurations
from codegen.kinds.pallet.program import (
    base_input,
    counter_names,
    counter_registers,
    holds_name,
    known_name,
    other_flags,
    written_register,
)
from codegen.kinds.pallet.reach import joints_of
from codegen.kinds.pallet.reload import reload_proof
from codegen.kinds.pallet.restart import expected
from codegen.kinds.pallet.section import pallets_of
from codegen.kinds.pallet.station import BoxLost, PalletTaken, ResetAnswered, ResetWhileAsked, SupplyLate
from codegen.model.io import LATE_SHARE, signal_name
from codegen.reference import home_move
from codegen.sim.gripper import Gripper
from codegen.sim.operator import Operator
from codegen.verify.plan import START_AWAY_DEG, Case, Setup, tool_inputs

# a swap of the done pallet takes this many of the pallet's interlock timeouts: the program's wait for it outlasts its
# own timeout (a swap is no fault)
SWAP_TIMEOUTS = 3


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
    if target.name in pallet.io.reset:  # the PLC swaps a done pallet (the case's swaps), then resets its counters
        devices += (exchange(target, pallet, run.case),)
    toggle = written_register(cell, target, index)
    if toggle is not None:  # the PLC's block keeps the counters, copied from the program's registers at its toggle
        devices += (CounterLatch(*kept_names(cell, target, index), toggle[1], (run.case.layer, run.case.box)),)
    # the operator at the pendant: answers the question (after a stop in a release, or the store reloaded) as the case
    # says, or looks away (a dialog stays shown until the program's own timeout ends it)
    devices += (Operator([] if run.case.answer is None else [run.case.answer], then_silent=True),)
    select = None if run.pallet < 0 else run.pallet
    counters = {layer_name: run.case.layer, box_name: run.case.box}
    holds = holds_name(cell, target, index)
    if holds is not None:  # its store's flag: this program gripped what the gripper holds
        counters[holds] = run.case.closed and not run.case.foreign
    others = other_flags(cell, target, index)
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
        {**counters, **tool_inputs(cell, target.name), **base_input(cell, target, pallet, run.case.base_off)},
        devices,
        _signals(cell, target, pallet, run.case, select, pallets_of(cell)),
        start_joints(cell, index, source.target, case),
        (*kept_names(cell, target, index), *([] if holds is None else [holds]), *others, *([known] if known else [])),
    )


def exchange(target, pallet, case: PalletCase) -> PalletExchange:
    """The PLC and the fork-lift at a done pallet: the case's swaps, each after SWAP_TIMEOUTS interlock timeouts."""
    present = pallet.io.pallet_present.get(target.name)
    return PalletExchange(
        signal_name(target, "output", pallet.io.done[target.name]),
        signal_name(target, "input", pallet.io.reset[target.name]),
        None if present is None else signal_name(target, "input", present),
        case.exchanges,
        SWAP_TIMEOUTS * pallet.io.timeout_s,
        case.exchange_held,
    )


def start_joints(cell, index: int, target_name: str, case: Case):
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
