"""What a new user's pallet cell is told: a pallet in the floor or a stack into a solid at load, by key and with the
numbers; a clearance refusal's fix that follows the move that comes too near; one name for a pallet everywhere."""

from __future__ import annotations

from pathlib import Path

import pytest
from support.cells import replace_once

from codegen.model.cell import CellError, load_cell
from codegen.model.robot import Margins

EXAMPLES = Path(__file__).resolve().parents[2] / "codegen" / "examples" / "pallets"
TESTMAT = (EXAMPLES / "testmat_pallet.toml").read_text(encoding="utf-8")
EUR = (EXAMPLES / "eur_pallet.toml").read_text(encoding="utf-8")
TESTMAT_FRAME = "origin = [650.0, -50.0, 50.0], x_point = [750.0, -50.0, 50.0], xy_point = [650.0, 30.0, 50.0]"


def _error(write_cell, text: str) -> str:
    with pytest.raises(CellError) as info:
        load_cell(write_cell(text))
    return str(info.value)


def _deck_at(z: float) -> str:
    return replace_once(TESTMAT, TESTMAT_FRAME, TESTMAT_FRAME.replace("50.0]", f"{z}]"))


@pytest.mark.parametrize(
    ("deck", "said"),
    [
        (
            0.0,
            "stands in the floor: its top (the plane of frame's origin, x_point and xy_point) is at z = 0.0 mm at "
            "its lowest corner, on the floor at z = 0 mm (cell.world.floor_z_mm)",
        ),
        (
            -30.0,
            "stands in the floor: its top (the plane of frame's origin, x_point and xy_point) is at z = -30.0 mm "
            "at its lowest corner, 30.0 mm below the floor at z = 0 mm",
        ),
        (
            12.5,
            "stands too near the floor: its top (the plane of frame's origin, x_point and xy_point) is at z = 12.5 "
            "mm at its lowest corner, 12.5 mm above the floor at z = 0 mm",
        ),
    ],
)
def test_a_pallet_taught_on_or_in_the_floor_is_told_so_at_its_frame(write_cell, deck, said):
    """Generate used to refuse the way home from the first box ("the part dips below the floor ... teach the poses of
    the move higher"); the cell is refused at load, at the frame's line, with the heights and the keys to change."""
    message = _error(write_cell, _deck_at(deck))
    assert "line 33: pallet[0].frame: pallet 'testmat' " + said in message
    assert "within the clearance of 20 mm (cell.world.clearance_mm) of the floor" in message
    assert f"set cell.world.floor_z_mm to the floor's height (at most {deck - 20.0:.1f} mm)" in message


def test_the_floor_check_follows_the_floor_and_the_clearance(write_cell):
    """The floor lowered under the pallet's top by the clearance, the same pallet loads; a tilted pallet is judged by
    its lowest corner."""
    lowered = _deck_at(0.0).replace("[cell.io]", "[cell.world]\nfloor_z_mm = -20.0\n\n[cell.io]", 1)
    assert load_cell(write_cell(lowered)).sections["pallet"][0].origin[2] == 0.0
    tilted = replace_once(TESTMAT, "x_point = [750.0, -50.0, 50.0]", "x_point = [750.0, -50.0, 5.0]")
    message = _error(write_cell, tilted)  # x 45 mm down over 100 mm along: 104 mm along it is 42.7 mm lower
    assert "stands too near the floor" in message and "is at z = 7.3 mm at its lowest corner" in message


def test_a_stack_through_a_declared_solid_says_how_many_layers_fit(write_cell):
    beam = "solids.beam = { box = [4000.0, 300.0, 200.0], pose = [0.0, 1500.0, 700.0, 0.0, 0.0, 0.0] }\n"
    text = replace_once(EUR, "solids.fence_back", beam + "solids.fence_back")
    message = _error(write_cell, text)
    # the deck at -500 mm, 5 layers of 250 mm and 2 sheets of 3 mm: the top at 756 mm, the beam's bottom at 600 mm
    assert (
        "pallet[0].layers: pallet 'eur': its full stack (5 layers, 1256 mm above the pallet's top) reaches 156.0 mm "
        "into the solid 'beam' (cell.world.solids.beam); at most 4 layers fit below it" in message
    )
    assert load_cell(write_cell(text.replace("layers = 5 ", "layers = 4 ", 1))).sections["pallet"][0].layers == 4


TALL = (Path(__file__).parent / "cells" / "tall_stack.toml").read_text(encoding="utf-8")


def _refusal(write_cell, text: str) -> str:
    from codegen.generate import GenerateError, check_clearance

    with pytest.raises(GenerateError) as info:
        check_clearance(load_cell(write_cell(text)), None)
    return str(info.value)


def test_the_way_home_through_a_tall_stack_names_the_transit_height_and_the_home(write_cell):
    """The way home after a stop at the last box swings the box through the top layer: the fix used to be "move
    'pallet left: layer 12 box 2' away from the move's path" (a box of the stack, which no key moves); it names the
    keys of the cause: the transit height, the layers, and the home that holds the box below the stack's top."""
    message = _refusal(write_cell, TALL)
    assert "pallet 'left' the way home from layer 12 box 4 target: home (kuka, KR 210 R2700 extra): the " in message
    assert "'pallet left: layer 12 box 2'" in message and "move 'pallet left" not in message
    assert (
        "after a stop the way home lifts the box to the transit height over the full stack (its top at z = 1340.0 mm) "
        "and swings it above the pallet's centre and home in joint moves: raise the transit height "
        "(transit_clearance_mm of pallet 'left': 10 mm) or lower the stack (layers: 12); the home "
        "[cell.robot.home] kuka = [0, -90, 90, 0, 90, 0] holds the box's bottom at z = 1199.0 mm, below the full "
        "stack's top (z = 1340.0 mm): give the arm a home above it or away from the pallet" in message
    )


@pytest.mark.slow
@pytest.mark.parametrize(
    ("old", "new"),
    [
        ("box_mass_kg = 10.0", "box_mass_kg = 10.0\ntransit_clearance_mm = 150.0"),
        ("[cell.tool]", "[cell.robot.home]\nkuka = [0.0, -110.0, 80.0, 0.0, 90.0, 0.0]\n\n[cell.tool]"),
    ],
)
def test_the_fixes_the_way_home_refusal_names_clear_the_cell(write_cell, old, new):
    """Each fix the refusal suggests, applied, lets the cell's every move clear (a raised transit height; a home
    higher than the stack's top)."""
    from codegen.generate import check_clearance

    assert check_clearance(load_cell(write_cell(replace_once(TALL, old, new))), None)


def test_a_way_home_the_arm_cannot_follow_is_refused_without_a_traceback(write_cell):
    """The way home from the first box (only the proof plans it) flips the arm's configuration on its way up: a
    ReachError that generate's clearance check let through as a traceback; now refused, naming the way home."""
    text = TALL.replace("1100.0, -100.0]", "900.0, -100.0]").replace("1700.0, -100.0]", "1500.0, -100.0]")
    message = _refusal(write_cell, text)
    assert (
        "pallet 'left' the way home from layer 1 box 1 target: up to the transit height (kuka, KR 210 R2700 extra): "
        "the linear move would change the arm's configuration" in message
    )


@pytest.mark.parametrize(
    ("where", "other", "fix"),
    [
        ("layer 12 box 1 transit", "pallet left: stack below layer 12", "the move swings over the stack"),
        ("layer 3 box 2 over Q", "pallet left: layer 3 box 1", "the move swings over the stack"),
        ("the way home from layer 1 box 1 target: safe above the pallet", "pallet left", "after a stop the way home"),
        ("the way home from layer 1 box 1 target: back along the tool's z", "pallet left", None),
        ("layer 12 box 1 transit", "pallet left: pick place", None),
        ("layer 12 box 1 transit", "fence_back", None),
        ("layer 12 box 1 entry", "pallet left: layer 12 box 2", None),
    ],
)
def test_the_stack_fix_follows_the_move_and_the_solid(where, other, fix):
    """The pallet's fix applies to its own stack only, on the moves that swing over it (a transit, over Q, the way
    home's joint moves); elsewhere the proof's own fix stands (None)."""
    from types import SimpleNamespace

    from codegen.kinds.pallet.refusals import StackFix

    cell = load_cell(Path(__file__).parent / "cells" / "tall_stack.toml")
    pallet = cell.sections["pallet"][0]
    path = SimpleNamespace(target="kuka")
    text = StackFix(pallet, ("left", "right")).text(cell, path, SimpleNamespace(where=f"pallet 'left' {where}"), other)
    if fix is None:
        assert text is None
    else:
        assert text.startswith(fix) and "transit_clearance_mm of pallet 'left': 10 mm" in text


def _stats_of(margins_deg: list[float], names: list[str]):
    """ArmStats after one run whose moves' least joint margins are these (axis 1 of a UR5e turned towards +360)."""
    from types import SimpleNamespace

    from codegen.robot.arms import find_arm
    from codegen.robot.expect import ArmStats

    arm = find_arm("UR5e")
    cell = SimpleNamespace(robot=SimpleNamespace(arms={"ur": arm}, margins=Margins(5.0, 5.0)))
    moves = [SimpleNamespace(joints=[360.0 - m, -90, 90, -90, 90, 0], line=10 + i) for i, m in enumerate(margins_deg)]
    stats = ArmStats()
    stats.add(cell, "ur", moves, lambda: "full_stack pallet testmat layer 1 box 1", names)
    return stats


def test_verify_names_the_first_move_of_a_tied_least_margin_and_its_name():
    """Margins within the joints' tolerance (0.05 deg: JOINT_TOLERANCE_DEG) are one margin: the first move in the
    run's order is named, with the expected move's name (a pallet's box), as generate names it; the least printed."""
    stats = _stats_of([20.0, 10.03, 10.0, 12.0], ["home", "layer 2 box 1 transit", "layer 4 box 1 transit", "x"])
    assert stats.joint_margin_deg == pytest.approx(10.0)
    assert stats.joint_margin_at == (
        "axis 1 at 350.0 deg, move 2 (line 11: layer 2 box 1 transit), full_stack pallet testmat layer 1 box 1"
    )
    later = _stats_of([10.01], ["layer 5 box 1 transit"])  # a later case's run: within the tie, not named
    stats.merge(later)
    assert "layer 2 box 1 transit" in stats.joint_margin_at
    lower = _stats_of([9.9], ["layer 6 box 1 transit"])  # lower by more than the tie: named
    stats.merge(lower)
    assert "layer 6 box 1 transit" in stats.joint_margin_at and stats.joint_margin_deg == pytest.approx(9.9)


@pytest.mark.slow
def test_generate_and_verify_name_the_same_move_for_the_least_joint_margin():
    """The UR5e on testmat: generate's reach proof names layer 2 box 1's transit (layers 2 and 4 tie: the same
    margin at each of their box 1 moves); verify's run of the whole stack names the same move (it named only the
    case, which starts at layer 1 box 1)."""
    from codegen.kinds.pallet.cases import verify_cases
    from codegen.kinds.pallet.plan import check
    from codegen.verify.programs import fresh_sources
    from codegen.verify.runner import run_cases

    cell = load_cell(EXAMPLES / "testmat_pallet.toml")
    (reach,) = [r for r in check(cell) if r.target == "ur"]
    assert reach.worst == "layer 2 box 1 transit"
    source = next(s for s in fresh_sources(cell, ["ur"]) if s.kind == "pallet")
    row = run_cases(cell, source, verify_cases(cell, source, 0)[:1], 200_000)
    assert row.arm.joint_margin_deg == pytest.approx(reach.joint_margin_deg, abs=0.05)
    assert f": {reach.worst}), full_stack" in row.arm.joint_margin_at


def test_a_swing_into_another_pallets_stack_names_both_pallets_keys(tmp_path):
    """Two pallets on one arm: the joint move onto the low pallet's transit swings the box through the tall pallet's
    stack. The refusal says whose stack it is and the keys of both pallets that fix it, not the proof's generic
    "move the solid away"."""
    from click.testing import CliRunner

    from codegen.cli import main

    cell = Path(__file__).parent / "cells" / "two_pallets.toml"
    result = CliRunner().invoke(main, ["generate", str(cell), "--out", str(tmp_path / "out")])
    assert result.exit_code == 2, result.output
    assert "pallet 'low' layer 1 box 1 transit" in result.output and "'pallet tall: stack" in result.output
    said = "the move swings into the stack of pallet 'tall' (full: 10 layers, its top at z = 1100.0 mm)"
    assert said in result.output
    assert "transit_clearance_mm of pallet 'low': 10 mm" in result.output
    assert "layers of pallet 'tall': 10" in result.output and "[[pallet]] frame" in result.output
    assert "Traceback" not in result.output and not (tmp_path / "out").exists()
