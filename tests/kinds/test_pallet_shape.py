"""The pallet kind's geometry (shape.py): made once per cell, the same on every target, handed down with the cell (a
cell made or loaded after another, even at the same address, gets its own), and gone with its cell."""

from __future__ import annotations

import builtins
import gc
import weakref
from dataclasses import replace

import numpy as np
from support.cells import EXAMPLES

from codegen.kinds.pallet import shape as shape_module
from codegen.kinds.pallet.report import pallet_report
from codegen.kinds.pallet.section import pallets_of
from codegen.kinds.pallet.shape import PalletShape, full_cycle, pallet_shape, shape
from codegen.model.cell import Cell, load_cell

TESTMAT = EXAMPLES["testmat_pallet"]
TEXT = TESTMAT.read_text(encoding="utf-8")
FRAME = "frame = { origin = [650.0, -50.0, 50.0], x_point = [750.0, -50.0, 50.0], xy_point = [650.0, 30.0, 50.0] }"


def _moved(dx: float) -> str:
    """Source 004's test pallet with its three taught points dx mm further along the base's x."""
    assert TEXT.count(FRAME) == 1
    moved = (
        f"frame = {{ origin = [{650.0 + dx}, -50.0, 50.0], x_point = [{750.0 + dx}, -50.0, 50.0], "
        f"xy_point = [{650.0 + dx}, 30.0, 50.0] }}"
    )
    return TEXT.replace(FRAME, moved)


def test_the_shape_is_the_pallet_as_the_cell_file_gives_it():
    """testmat: the three points span the base's x and y from (650, -50, 50); 5 layers of 26 mm boxes, 6 a layer; the
    safe pose over the pallet's centre (52, 39) at the full stack's top (130) and the transit height over it, the
    higher of the box's height and the clearance (26 + 10) and the entry (50): z 50 + 130 + 50 in the base."""
    cell = load_cell(TESTMAT)
    (own,) = shape(cell).pallets
    np.testing.assert_allclose(own.pallet2base, [[1, 0, 0, 650], [0, 1, 0, -50], [0, 0, 1, 50], [0, 0, 0, 1]])
    assert own.tops == (0.0, 26.0, 52.0, 78.0, 104.0, 130.0)
    assert own.boxes == 30 and own.layer_counts() == {n: 6 for n in range(1, 6)}
    assert [len(own.layouts[name]) for name in ("p1", "p2")] == [6, 6]
    first = own.placements[0]  # p1's first box, (13, 26) turned 90 deg clockwise, on the deck: its top at 26
    assert (first.layer, first.number, first.box.ccw_deg) == (1, 1, -90.0)
    np.testing.assert_allclose(first.target[:3, 3], [13.0, 26.0, 26.0])
    assert own.items[0].key == (1, 1) and own.items[-1].key == (5, 6)
    np.testing.assert_allclose(own.safe2base[:3, 3], [702.0, -11.0, 230.0])
    assert shape(cell).way_up_z == 230.0


def _fresh(tmp_path, text: str = TEXT) -> Cell:
    """A cell read from a file of its own (the tests' loader keeps one Cell per bundled file and process)."""
    path = tmp_path / "testmat.toml"
    path.write_text(text, encoding="utf-8")
    return load_cell(path)


def test_the_shape_is_made_once_per_cell_and_read_by_every_target(tmp_path, monkeypatch):
    """The page, the solids, the report and every target's full cycle read one shape and one full cycle per pallet."""
    made, cycles = [], []
    real_of, real_expected = PalletShape.of, shape_module.expected
    monkeypatch.setattr(PalletShape, "of", classmethod(lambda cls, pallet: made.append(pallet) or real_of(pallet)))
    monkeypatch.setattr(shape_module, "expected", lambda *a: cycles.append(a) or real_expected(*a))
    cell = _fresh(tmp_path)
    kind = cell.kinds["pallet"]
    (pallet,) = pallets_of(cell)
    kind.scene.objects(cell)
    kind.scene.solids(cell)
    pallet_report(cell, pallet)
    cycle = full_cycle(cell, pallet)
    assert full_cycle(cell, pallet) is cycle and len(cycle) > 30 * 4
    assert made == [pallet] and len(cycles) == 1
    assert cell.plans[shape_module.KEY] is shape(cell)
    changed = replace(cell, sections=dict(cell.sections))  # another cell: its own shape, none inherited
    assert changed.plans == {} and shape(changed) is not shape(cell) and len(made) == 2


def test_a_pallet_not_the_cells_own_is_worked_out_for_itself_and_not_kept():
    cell = load_cell(TESTMAT)
    (pallet,) = pallets_of(cell)
    higher = replace(pallet, box=(52.0, 26.0, 30.0))
    assert shape(cell).of(higher) is None
    assert pallet_shape(cell, higher).tops[-1] == 150.0 and pallet_shape(cell, pallet).tops[-1] == 130.0
    own = full_cycle(cell, pallet)
    other = full_cycle(cell, higher)
    assert full_cycle(cell, pallet) is own and full_cycle(cell, higher) is not other
    assert list(shape(cell).cycles) == [pallet.name]
    assert _top_target_z(other) - _top_target_z(own) == 20.0  # 5 layers of 30 mm boxes, not 26


def test_a_cell_made_after_another_at_the_same_address_gets_its_own_shape(tmp_path, monkeypatch):
    """Cells with the pallet moved by a millimetre each, made one after another, the one before dropped, and every
    cell given one address (id() patched: what CPython does when a new cell takes a dropped one's memory): each one's
    frame, solids and way home stand at its own pallet. A store keyed by id() would hand it the dropped cell's, a
    millimetre off."""
    real_id = builtins.id
    monkeypatch.setattr(builtins, "id", lambda thing: 1 if isinstance(thing, Cell) else real_id(thing))
    path = tmp_path / "moved.toml"
    for i in range(3):
        path.write_text(_moved(float(i)), encoding="utf-8")
        cell = load_cell(path)
        assert id(cell) == 1
        (own,) = shape(cell).pallets
        np.testing.assert_allclose(own.pallet2base[:3, 3], [650.0 + i, -50.0, 50.0])
        np.testing.assert_allclose(own.safe2base[:3, 3], [702.0 + i, -11.0, 230.0])
        deck = cell.kinds["pallet"].scene.solids(cell)["pallet testmat"]
        np.testing.assert_allclose(deck.pose[:3, 3][:2], [702.0 + i, -11.0])
        assert full_cycle(cell, own.pallet)[0].tcp2base is not None
        np.testing.assert_allclose(_first_target(cell), [663.0 + i, -24.0, 76.0])
        del cell, own
        gc.collect()


def _top_target_z(cycle) -> float:
    """The highest place a box of the cycle is put down (base z, mm)."""
    return max(float(m.tcp2base[2, 3]) for m in cycle if m.name.endswith("target"))


def _first_target(cell) -> np.ndarray:
    """Where the full cycle puts the first box down (base frame, mm)."""
    move = next(m for m in full_cycle(cell, pallets_of(cell)[0]) if m.name.endswith("target"))
    return move.tcp2base[:3, 3]


def test_a_dropped_cell_leaves_nothing(tmp_path):
    """Once the cell is dropped its shape and its full cycles go with it: no store outlives the cell."""
    cell = _fresh(tmp_path)
    (pallet,) = pallets_of(cell)
    kind = cell.kinds["pallet"]
    kind.scene.objects(cell)
    kind.scene.solids(cell)
    cycle = full_cycle(cell, pallet)
    gone = [weakref.ref(x) for x in (cell, shape(cell), shape(cell).pallets[0], pallet, cycle[0])]
    del cell, pallet, cycle, kind
    gc.collect()
    assert [ref() is None for ref in gone] == [True] * len(gone)
