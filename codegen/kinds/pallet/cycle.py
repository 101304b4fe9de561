"""The float64 reference of a stacking program: from its counters, every move and gripper output to the full pallet."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from codegen.guard import NO_FEEDBACK, NOT_RELEASED, halt_message
from codegen.kinds.pallet.analysis import frame_matrix
from codegen.kinds.pallet.section import Pallet
from codegen.kinds.pallet.stack import placements

FULL = "pallet_full"
COUNTERS = "pallet_counters"


def full_message(pallet: Pallet) -> str:
    return f"pallet {pallet.name} is full: swap it, then set layer 1 and box 1"


def empty_message(pallet: Pallet) -> str:
    top = layer_counts(pallet)[pallet.layers]
    return f"pallet {pallet.name} is empty: bring a full one, then set layer {pallet.layers} and box {top}"


def held_message(pallet: Pallet) -> str:
    return f"pallet {pallet.name}: the gripper holds a box (its sensor is on): take it out, then start again"


def counters_message(pallet: Pallet) -> str:
    return f"pallet {pallet.name}: layer or box counter out of range"


@dataclass(frozen=True)
class PalletCase:
    """A run of the stacking program: its counters when it starts and how the gripper answers."""

    category: str
    layer: int
    box: int
    gripper: str = "prompt"  # codegen.sim.gripper.Gripper behaviours
    closed: bool = False  # the gripper's sensor on at the start: it holds a box (a cycle stopped mid-way)


@dataclass(frozen=True)
class ExpectedMove:
    kind: str  # "joint" or "linear"
    tcp2base: np.ndarray  # 4x4 mm
    name: str  # for the report: "layer 2 box 3 entry"
    speed_mm_s: float
    exact: bool  # a stop at the pose (no blending)


@dataclass(frozen=True)
class Expected:
    moves: tuple[ExpectedMove, ...]
    outputs: tuple[tuple[bool, int], ...]  # (gripper output value, moves commanded before it)
    halt: str | None  # the operator's message, None: the program ends (the pallet is full)
    counters: tuple[int, int]  # layer and box when the run ends: the box to place next


def layer_counts(pallet: Pallet) -> dict[int, int]:
    counts: dict[int, int] = {}
    for p in placements(pallet):
        counts[p.layer] = counts.get(p.layer, 0) + 1
    return counts


def expected(cell, pallet: Pallet, case: PalletCase) -> Expected:
    """What the pallet's program does in this case (stacking or unstacking, as the pallet's mode)."""
    return (unstacking if pallet.mode == "unstack" else stacking)(cell, pallet, case)


def above_pick(pallet: Pallet) -> np.ndarray:
    """Q lifted by pick_lift along the base's z (tcp2base, mm): where the arm comes down to Q from and
    lifts the box back to."""
    above = pallet.pick.matrix().copy()
    above[2, 3] += pallet.pick_lift
    return above


def _in_range(pallet: Pallet, counts: dict[int, int], case: PalletCase) -> bool:
    return 1 <= case.layer <= pallet.layers and 1 <= case.box <= counts[case.layer]


def unstacking(cell, pallet: Pallet, case: PalletCase) -> Expected:
    """Release at the start; then per box from the counters, the top layer first and each layer in the
    reverse of its placing order: entry (joint), approach, target (slow, exact), grip, retreat (slow),
    entry, above Q (joint), Q (slow), release, above Q (slow); the counters move to the next box once
    the grip is confirmed (the box has left the pallet). An empty pallet (layer 0, box 0) or counters out
    of range stop before any move."""
    counts = layer_counts(pallet)
    grip, start = cell.io.value, (case.layer, case.box)
    if start == (0, 0):
        return Expected((), (), empty_message(pallet), start)
    if not _in_range(pallet, counts, case):
        return Expected((), (), counters_message(pallet), start)
    if case.closed:  # a box in the gripper: opening it anywhere would drop it
        return Expected((), (), held_message(pallet), start)
    frame, pick, above = frame_matrix(pallet), pallet.pick.matrix(), above_pick(pallet)
    travel, work = cell.motion.speed_mm_s, cell.motion.work_speed_mm_s
    moves: list[ExpectedMove] = []
    outputs: list[tuple[bool, int]] = [(not grip, 0)]
    counters = start
    for p in reversed(placements(pallet)):
        if (p.layer, p.number) > start:
            continue
        where = f"layer {p.layer} box {p.number}"
        moves.append(ExpectedMove("joint", frame @ p.entry, f"{where} entry", travel, True))
        moves.append(ExpectedMove("linear", frame @ p.approach, f"{where} approach", travel, True))
        moves.append(ExpectedMove("linear", frame @ p.target, f"{where} target", work, True))
        outputs.append((grip, len(moves)))
        if case.gripper == "silent":
            return Expected(tuple(moves), tuple(outputs), halt_message(cell, NO_FEEDBACK, None, 0), counters)
        if p.number > 1:
            counters = (p.layer, p.number - 1)
        else:
            counters = (p.layer - 1, counts[p.layer - 1]) if p.layer > 1 else (0, 0)
        moves.append(ExpectedMove("linear", frame @ p.retreat, f"{where} retreat", work, True))
        moves.append(ExpectedMove("linear", frame @ p.entry, f"{where} entry", travel, True))
        moves.append(ExpectedMove("joint", above, f"{where} above Q", travel, True))
        moves.append(ExpectedMove("linear", pick, f"{where} place at Q", work, True))
        outputs.append((not grip, len(moves)))
        if case.gripper == "stuck":  # the box never leaves the gripper at Q: it is off the pallet
            return Expected(tuple(moves), tuple(outputs), halt_message(cell, NOT_RELEASED, None, 0), counters)
        moves.append(ExpectedMove("linear", above, f"{where} lift from Q", work, True))
    return Expected(tuple(moves), tuple(outputs), None, counters)


def stacking(cell, pallet: Pallet, case: PalletCase) -> Expected:
    """Release at the start; then per box from the counters: above Q (joint), Q (slow), grip, above Q
    (slow), entry (joint), approach,
    target (slow, exact), release, retreat (slow), entry; the counters advance once the release is
    confirmed. A full pallet or counters out of range stop before any move."""
    counts = layer_counts(pallet)
    grip = cell.io.value
    if case.layer == pallet.layers + 1 and case.box == 1:
        return Expected((), (), full_message(pallet), (case.layer, case.box))
    if not _in_range(pallet, counts, case):
        return Expected((), (), counters_message(pallet), (case.layer, case.box))
    if case.closed:  # a box in the gripper: opening it anywhere would drop it
        return Expected((), (), held_message(pallet), (case.layer, case.box))
    frame, pick, above = frame_matrix(pallet), pallet.pick.matrix(), above_pick(pallet)
    travel, work = cell.motion.speed_mm_s, cell.motion.work_speed_mm_s
    moves: list[ExpectedMove] = []
    outputs: list[tuple[bool, int]] = [(not grip, 0)]
    counters = (case.layer, case.box)
    for p in placements(pallet):
        if (p.layer, p.number) < (case.layer, case.box):
            continue
        where = f"layer {p.layer} box {p.number}"
        moves.append(ExpectedMove("joint", above, f"{where} above Q", travel, True))
        moves.append(ExpectedMove("linear", pick, f"{where} pick", work, True))
        outputs.append((grip, len(moves)))
        if case.gripper == "silent":
            return Expected(tuple(moves), tuple(outputs), halt_message(cell, NO_FEEDBACK, None, 0), counters)
        moves.append(ExpectedMove("linear", above, f"{where} lift from Q", work, True))
        moves.append(ExpectedMove("joint", frame @ p.entry, f"{where} entry", travel, True))
        moves.append(ExpectedMove("linear", frame @ p.approach, f"{where} approach", travel, True))
        moves.append(ExpectedMove("linear", frame @ p.target, f"{where} target", work, True))
        outputs.append((not grip, len(moves)))
        if case.gripper == "stuck":  # the box never leaves the gripper: the counters stay at it
            return Expected(tuple(moves), tuple(outputs), halt_message(cell, NOT_RELEASED, None, 0), counters)
        counters = (p.layer, p.number + 1) if p.number < counts[p.layer] else (p.layer + 1, 1)
        moves.append(ExpectedMove("linear", frame @ p.retreat, f"{where} retreat", work, True))
        moves.append(ExpectedMove("linear", frame @ p.entry, f"{where} entry", travel, True))
    return Expected(tuple(moves), tuple(outputs), None, counters)


def cases(pallet: Pallet, rng) -> list[PalletCase]:
    """The full stack from its first box (stacking: layer 1 box 1; unstacking: the top layer's last box);
    restarts at random boxes (the counters preset, as a restart finds them); a full (empty) pallet;
    counters out of range; the gripper never closing, never opening."""
    counts = layer_counts(pallet)
    if pallet.mode == "unstack":
        out = [PalletCase("full_unstack", pallet.layers, counts[pallet.layers])]
        for _ in range(3):
            layer = rng.randint(1, pallet.layers)
            out.append(PalletCase("restart", layer, rng.randint(1, counts[layer])))
        out += [PalletCase("restart", 1, 1), PalletCase("pallet_empty", 0, 0)]
        out += [PalletCase("bad_counters", 0, 1), PalletCase("bad_counters", 1, counts[1] + 1)]
        out += [PalletCase("bad_counters", pallet.layers + 1, 1), PalletCase("bad_counters", 2, 0)]
        top = (pallet.layers, counts[pallet.layers])
        out += [PalletCase("gripper_silent", *top, "silent"), PalletCase("held_at_start", *top, closed=True)]
        out.append(PalletCase("gripper_stuck_at_q", *top, "stuck"))
        return out
    out = [PalletCase("full_stack", 1, 1)]
    for _ in range(3):
        layer = rng.randint(1, pallet.layers)
        out.append(PalletCase("restart", layer, rng.randint(1, counts[layer])))
    out.append(PalletCase("restart", pallet.layers, counts[pallet.layers]))  # the last box
    out.append(PalletCase("pallet_full", pallet.layers + 1, 1))
    out += [PalletCase("bad_counters", 0, 1), PalletCase("bad_counters", 1, counts[1] + 1)]
    out += [PalletCase("bad_counters", pallet.layers + 1, 2), PalletCase("bad_counters", 2, 0)]
    out += [PalletCase("gripper_silent", 1, 1, "silent"), PalletCase("held_at_start", 1, 1, closed=True)]
    # it never lets the box go at the target: the counters must stay at that box
    layer = min(2, pallet.layers)
    out.append(PalletCase("gripper_stuck_at_target", layer, counts[layer], "stuck"))
    return out
