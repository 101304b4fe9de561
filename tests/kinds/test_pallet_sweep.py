"""The carried box's sweep over the stack: the plan's straight segments, checked against the boxes already placed."""

from __future__ import annotations

import itertools
from dataclasses import replace

import numpy as np

from codegen.kinds.pallet.analysis import frame_matrix
from codegen.kinds.pallet.cycle import PalletCase, expected, start_counters
from codegen.kinds.pallet.section import pallets_of
from codegen.kinds.pallet.sweep import sweeps
from codegen.model.cell import load_cell
from tests.kinds.test_pallet import EXAMPLES


def _plan(name: str):
    cell = load_cell(EXAMPLES / name)
    pallet = pallets_of(cell)[0]
    return pallet, frame_matrix(pallet), expected(cell, pallet, PalletCase("t", *start_counters(pallet))).moves


def _direct(moves):
    """The plan without the transit: from above Q a joint move straight to the entry (and back to above Q)."""
    out = []
    for move in moves:
        if move.name.endswith((" up from Q", " transit", " over Q")):
            continue
        joint = move.name.endswith(" entry") and out and out[-1].name.endswith(("lift from Q", "above Q"))
        out.append(replace(move, kind="joint") if joint else move)
    return out


def _over_the_top(pallet, frame, moves, height_mm: float):
    """The plan with each joint move into an entry made by way of poses height_mm above the pallet (pallet frame):
    up where the arm is, over to above the entry, down to it."""
    out = [moves[0]]
    for before, move in itertools.pairwise(moves):
        if move.kind == "joint" and move.name.endswith("entry") and move.carrying:
            for pose in (before.tcp2base, move.tcp2base):
                local = np.linalg.inv(frame) @ pose
                local[2, 3] = height_mm
                over = move.name.rsplit(" ", 1)[0] + " over"
                out.append(replace(move, kind="linear", tcp2base=frame @ local, name=over))
        out.append(move)
    return out


def test_the_straight_path_from_above_q_to_the_entry_passes_through_the_layer():
    """Box 2 of layer 1 from above Q (30 mm over the deck) straight up to its entry crosses box 1 (its top at 26 mm);
    the plan's rise to the transit height first passes."""
    pallet, frame, moves = _plan("testmat_pallet.toml")
    assert sweeps(pallet, frame, moves) is None
    found = sweeps(pallet, frame, _direct(moves))
    assert found is not None and found.startswith("layer 1 box 2 entry") and "top of layer 1 box 1" in found


def test_the_bundled_unstacking_plan_passes_and_fails_without_its_transit():
    pallet, frame, moves = _plan("eur_pallet.toml")
    assert sweeps(pallet, frame, moves) is None
    assert sweeps(pallet, frame, _direct(moves)) is not None


def test_a_path_over_the_full_stack_and_the_final_descents_pass():
    pallet, frame, moves = _plan("testmat_pallet.toml")
    moves = _direct(moves)
    assert sweeps(pallet, frame, _over_the_top(pallet, frame, moves, 5 * 26 + 26 + 1)) is None
    # 1 mm lower than the full stack plus a box: the top layer's later boxes cross the earlier ones
    assert sweeps(pallet, frame, _over_the_top(pallet, frame, moves, 5 * 26 + 26 - 1)) is not None


def _sheet_direct(moves):
    """The plan with each slip sheet carried straight from above the sheet stack to its entry in a joint move (no rise
    to the transit height first)."""
    out = []
    for move in moves:
        if move.sheet and move.name.endswith((" up from the sheet stack", " transit")):
            continue
        joint = move.sheet and move.name.endswith(" entry") and out[-1].name.endswith("lift from the sheet stack")
        out.append(replace(move, kind="joint") if joint else move)
    return out


def test_the_carried_slip_sheet_rises_to_the_transit_height_before_it_swings():
    """The EUR cell's sheets lie in a stack below the pallet's top: carried straight from above it to the sheet's
    entry, the sheet (taken as the pallet's size) passes below the tops of layer 2; the plan rises first and passes."""
    pallet, frame, moves = _plan("eur_pallet.toml")
    sheets = [m for m in moves if m.sheet]
    assert [m.name for m in sheets[:5]] == [
        "layer 3 sheet lift from the sheet stack",
        "layer 3 sheet up from the sheet stack",
        "layer 3 sheet transit",
        "layer 3 sheet entry",
        "layer 3 sheet target",
    ]
    assert sweeps(pallet, frame, moves) is None
    found = sweeps(pallet, frame, _sheet_direct(moves))
    assert found is not None and found.startswith("layer 3 sheet entry") and "carried sheet's bottom" in found, found
