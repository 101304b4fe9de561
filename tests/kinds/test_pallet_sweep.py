"""The gripper's sweep over the stack: the carried box against the boxes already placed, the empty gripper against the
boxes on the pallet; the plan's straight segments, or a joint move through the arm's joint space."""

from __future__ import annotations

import itertools
from dataclasses import replace

import numpy as np

from codegen.kinds.pallet import judge
from codegen.kinds.pallet.analysis import frame_matrix
from codegen.kinds.pallet.cycle import PalletCase, safe_pose, sheet_below, start_counters
from codegen.kinds.pallet.reach import plan
from codegen.kinds.pallet.restart import expected
from codegen.kinds.pallet.section import pallets_of
from codegen.kinds.pallet.shape import PalletShape
from codegen.kinds.pallet.sweep import sweeps
from codegen.model.cell import load_cell
from tests.kinds.test_pallet import EXAMPLES


def _plan(name):
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


def test_the_straight_path_from_above_q_to_the_entry_passes_through_the_layer(tmp_path):
    """With the entry as low as the pallet kind accepts (one box height, 26 mm, over the target), box 2 of layer 1 from
    above Q (30 mm over the deck) straight up to its entry crosses box 1 (its top at 26 mm); the plan's rise to the
    transit height first passes."""
    text = (EXAMPLES / "testmat_pallet.toml").read_text(encoding="utf-8")
    assert text.count("entry_dz = 50.0") == 1
    (tmp_path / "low_entry.toml").write_text(text.replace("entry_dz = 50.0", "entry_dz = 26.0"), encoding="utf-8")
    pallet, _frame, moves = _plan(tmp_path / "low_entry.toml")
    assert sweeps(PalletShape.of(pallet), moves) is None
    found = sweeps(PalletShape.of(pallet), _direct(moves))
    assert found is not None and found.startswith("layer 1 box 2 entry") and "top of layer 1 box 1" in found


def test_the_bundled_unstacking_plan_passes_and_fails_without_its_transit():
    pallet, _frame, moves = _plan("eur_pallet.toml")
    assert sweeps(PalletShape.of(pallet), moves) is None
    assert sweeps(PalletShape.of(pallet), _direct(moves)) is not None


def test_a_path_over_the_full_stack_and_the_final_descents_pass():
    pallet, frame, moves = _plan("testmat_pallet.toml")
    moves = _direct(moves)
    assert sweeps(PalletShape.of(pallet), _over_the_top(pallet, frame, moves, 5 * 26 + 26 + 1)) is None
    # 1 mm lower than the full stack plus a box: the top layer's later boxes cross the earlier ones
    assert sweeps(PalletShape.of(pallet), _over_the_top(pallet, frame, moves, 5 * 26 + 26 - 1)) is not None


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
    pallet, _frame, moves = _plan("eur_pallet.toml")
    sheets = [m for m in moves if m.sheet]
    assert [m.name for m in sheets[:5]] == [
        "layer 3 sheet lift from the sheet stack",
        "layer 3 sheet up from the sheet stack",
        "layer 3 sheet transit",
        "layer 3 sheet entry",
        "layer 3 sheet target",
    ]
    assert sweeps(PalletShape.of(pallet), moves) is None
    found = sweeps(PalletShape.of(pallet), _sheet_direct(moves))
    assert found is not None and found.startswith("layer 3 sheet entry") and "carried sheet's bottom" in found, found


def _with_joints(cell, pallet, moves, target: str):
    """The moves from home with the joints the program moves through (verify's sweep), the arm's fk and the empty
    gripper's width."""
    from codegen.kinds.pallet.judge import _swept

    return _swept(cell, pallet, target, moves)


def _unstack_plan():
    cell = load_cell(EXAMPLES / "eur_pallet.toml")
    pallet = next(p for p in pallets_of(cell) if p.mode == "unstack")
    return cell, pallet, expected(cell, pallet, PalletCase("t", *start_counters(pallet))).moves


def _unstack_direct(moves):
    """The unstacking plan as it was: from above Q (z 200) the empty gripper in one joint move straight to the next
    box's entry (no rise over Q, no joint move above the entry at the transit height)."""
    out = []
    for move in moves:
        if move.name.endswith(" up from Q") or (move.kind == "joint" and move.name.endswith(" transit")):
            continue
        if move.name.endswith(" entry") and (not out or out[-1].name.endswith(" lift from Q")):
            move = replace(move, kind="joint")
        out.append(move)
    return out


def test_the_empty_gripper_from_q_straight_to_the_next_entry_dips_into_the_top_layer(monkeypatch):
    """The unstacking plan's empty gripper rises over Q to the transit height, swings above the next box's entry and
    comes down: passes on both arms, followed through joint space. The joint move from above Q straight to the entry
    (the arm's joints a straight line between the two) takes the gripper's face below the top of a near-corner box of
    the top layer still on the pallet, with the 100 mm face and with the TCP point alone."""
    cell, pallet, moves = _unstack_plan()
    names = [m.name for m in moves[:3]]
    assert names == ["layer 5 box 8 transit", "layer 5 box 8 entry", "layer 5 box 8 approach"], names
    # the plan as it was came down to Q from z 200 (the default 100 mm lift; the cell lifts higher since it must
    # clear a box lying at Q): the direct joint move from there
    low = replace(pallet, pick_lift=100.0)
    low_moves = expected(cell, low, PalletCase("t", *start_counters(low))).moves
    for target in ("kuka", "abb"):
        swept, fk, width = _with_joints(cell, pallet, moves, target)
        assert fk is not None
        assert sweeps(PalletShape.of(pallet), swept, fk, width) is None
        with monkeypatch.context() as patch:  # the plan as it was: the configurations the controller takes from home
            patch.setattr(judge, "configurations", plan)
            old, fk, width = _with_joints(cell, low, _unstack_direct(low_moves), target)
        for face in (width, 0.0):
            found = sweeps(PalletShape.of(pallet), old, fk, face)
            assert found is not None and "empty gripper's face" in found and "top of layer 5 box" in found, found


def test_the_empty_gripper_leaving_a_stacked_box_swings_over_q_at_the_entry_height():
    """Stacking: from the entry of the box just placed the empty gripper swings over Q at that height, then comes
    straight down; a joint move from the entry straight down to above Q (200 mm over Q, below the top layers) passes
    through the boxes just placed (a straight segment; through the KR 210's joint space)."""
    cell = load_cell(EXAMPLES / "eur_pallet.toml")
    pallet = next(p for p in pallets_of(cell) if p.mode == "stack")
    moves = expected(cell, pallet, PalletCase("t", *start_counters(pallet))).moves
    direct = []
    for move in moves:
        if move.kind == "joint" and move.name.endswith((" over Q", " over the sheet stack")):
            continue
        if move.name.endswith((" above Q", " above the sheet stack")) and direct and direct[-1].name.endswith("entry"):
            move = replace(move, kind="joint")
        direct.append(move)
    assert sweeps(PalletShape.of(pallet), moves) is None
    found = sweeps(PalletShape.of(pallet), direct)
    assert found is not None and "empty gripper's face" in found, found
    for target in ("kuka", "abb"):
        assert sweeps(PalletShape.of(pallet), *_with_joints(cell, pallet, moves, target)) is None
    # through the KR 210's joint space the direct move dips below the layer just placed (the IRB 4600's clears it)
    found = sweeps(PalletShape.of(pallet), *_with_joints(cell, pallet, direct, "kuka"))
    assert found is not None and "empty gripper's face" in found, found


def test_the_way_home_passes_over_the_full_stack_with_a_held_box_clear_of_it():
    """The safe pose above the pallet's centre, which the way home after a stop passes with a held box: the box's
    bottom at least the transit clearance over the full stack's top (measured in the pallet frame from the box's
    height and the layers, not from the planner's transit height)."""
    for name in ("testmat_pallet.toml", "eur_pallet.toml"):
        cell = load_cell(EXAMPLES / name)
        for pallet in pallets_of(cell):
            top = pallet.layers * pallet.box[2] + sum(
                pallet.slip_thickness for layer in range(2, pallet.layers + 1) if sheet_below(pallet, layer)
            )
            bottom = safe_pose(pallet)[2, 3] - pallet.box[2]
            assert bottom - top >= pallet.transit_clearance_mm - 1e-9, (name, pallet.name, bottom - top)
