"""The pallet program's cases: a stack from its first item, restarts, resets, failures, stops in a release, reloads."""

from __future__ import annotations

import random
from dataclasses import dataclass, replace

from codegen.controllers import get_target
from codegen.kinds.pallet.cycle import PalletCase, done_counters
from codegen.kinds.pallet.kind import KIND
from codegen.kinds.pallet.program import base_input, holds_name, known_name, other_flags
from codegen.kinds.pallet.restart import NO, YES
from codegen.kinds.pallet.section import pallets_of
from codegen.kinds.pallet.shape import PalletShape, pallet_shape
from codegen.kinds.pallet.writer import FORMS_PER_PALLET
from codegen.verify.plan import Case

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


def own_cases(shape: PalletShape, rng) -> list[PalletCase]:
    """The whole pallet from its first item; restarts at random items and at the last (the counters preset, as a
    restart finds them), at a slip sheet; a full (empty) pallet, reset by the PLC or not, the reset ignored on a
    pallet not done; counters out of range; the gripper never closing or never opening; an interlock input that
    never comes on; the pallet taken away after the pick; the counters mid-pallet in their store after a reload of
    the program."""
    pallet, keys = shape.pallet, [item.key for item in shape.items]
    first, done = keys[0], done_counters(pallet)
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
        # the pallet done from its last item: the program waits above Q for the swap, then works the new pallet; the
        # PLC keeps that reset on (no swap confirmed: the stop)
        out.append(PalletCase("pallet_exchanged", *keys[-1], exchanges=1))
        out.append(PalletCase("exchange_reset_held", *keys[-1], exchanges=1, exchange_held=True))
        # the pallet done at the start with the reset off: the same wait above Q, then the new pallet; a reset kept on
        out.append(PalletCase("swapped_at_start", *done, exchanges=1))
        out.append(PalletCase("swapped_at_start", *done, exchanges=1, exchange_held=True))
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
        shape = pallet_shape(cell, pallets_of(cell)[index])
        own = own_cases(shape, random.Random(seed + index)) + _release_cases(shape, get_target(source.target))
        start = shape.items[0].key
        if holds_name(cell, get_target(source.target), index) is not None:  # the program can tell whose item it is
            own.append(PalletCase("held_by_another", *start, closed=True, foreign=True))
        if known_name(cell, get_target(source.target), index) is not None:  # the store loaded again from its file
            own += _reloaded_store_cases(shape.pallet, start)
        if base_input(cell, get_target(source.target), shape.pallet):  # the frame read from a base never measured
            own.append(PalletCase("base_not_measured", *start, base_off=True))
        if other_flags(cell, get_target(source.target), index):  # another pallet's flag left set, then a grip
            own.append(PalletCase("stale_flag", *start, stale=True))
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


def _reloaded_store_cases(pallet, first: tuple[int, int]) -> list[PalletCase]:
    """The counters' store loaded again from its file (as a reset of RAPID does) while the pallet is part-built: the
    counters are the file's (a new pallet's), its known flag FALSE. The operator does not answer, or says No: the
    stop before any move; Yes, or the PLC's reset handshake: the pallet's first item next (shown up to the wait for
    the pallet, which is not in place yet, so the run stays short); a reset the PLC keeps on: the stop."""
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


def _release_cases(shape: PalletShape, target) -> list[PalletCase]:
    """Stacking, a stop during a release; unstacking, a stop between the grip and Q (the counters marked, the layer
    negative): with the gripper empty the operator says whether the item is down (unstacking: back in its place on
    the pallet) and the counters move on (also past the last box) or stay, or a program that cannot ask stops with a
    message; with the item still held it is finished (unstacking: put down at Q, the counters past it)."""
    pallet, keys = shape.pallet, [item.key for item in shape.items]
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
