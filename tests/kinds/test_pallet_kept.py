"""The pallet's posture choice and its proofs kept by the value of what they read: a cell that differs in nothing
they read reuses them, one that differs in anything they read is proven anew."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from support.cells import example

from codegen.kept import Kept, digest
from codegen.kinds.pallet import posture
from codegen.kinds.pallet.shape import full_cycle

TARGET = "ur"


@pytest.fixture
def cell():
    return example("testmat_pallet")


def _pallets(cell, **changes):
    pallets = tuple(replace(p, **changes) for p in cell.sections["pallet"])
    return replace(cell, sections={**cell.sections, "pallet": pallets})


def _robot(cell, **changes):
    return replace(cell, robot=replace(cell.robot, **changes))


def _key(cell, cycle=None) -> bytes:
    pallet = cell.sections["pallet"][0]
    return posture.decision_key(cell, pallet, TARGET, full_cycle(cell, pallet) if cycle is None else cycle)[0]


def _value(made) -> bytes:
    """A choice and its proofs as a value, every field of it (none left out)."""
    return digest(made)[0]


def _unread(cell):
    """Every field UNREAD names changed at once: the file, the speeds, the masses, the blending, the interlocks'
    timeout."""
    cell = replace(cell, source="elsewhere/cell.toml", sha256="0" * 64, warnings=("elsewhere/cell.toml: a warning",))
    cell = replace(cell, motion=replace(cell.motion, speed_mm_s=123.0, work_speed_mm_s=45.0))
    cell = _robot(cell, tool=replace(cell.robot.tool, mass_kg=cell.robot.tool.mass_kg + 3.0))
    pallet = cell.sections["pallet"][0]
    return _pallets(cell, box_mass_kg=2.5, zone_mm=7.0, io=replace(pallet.io, timeout_s=9.0))


def _moved_home(cell):
    home = dict(cell.robot.home)
    first, *rest = (float(v) for v in home[TARGET])
    home[TARGET] = (first + 1.0, *rest)
    return _robot(cell, home=home)


def _tool_longer(cell):
    tool = cell.robot.tool
    along = np.eye(4)
    along[2, 3] = 5.0
    return _robot(cell, tool=replace(tool, tcp2flange=tool.tcp2flange @ along))


def _origin_up(cell):
    origin = cell.sections["pallet"][0].origin
    return _pallets(cell, origin=(origin[0], origin[1], origin[2] + 1.0))


# one field each that the posture's choice or its proofs read (the arm's start, the tool, the pallet's frame and
# name, the clearance, the way home's retreat and start tolerance, the transit height, the boxes)
READ = {
    "home": _moved_home,
    "tool_tcp": _tool_longer,
    "pallet_origin": _origin_up,
    "pallet_name": lambda c: _pallets(c, name="other"),
    "box": lambda c: _pallets(c, box=tuple(v + 1.0 for v in c.sections["pallet"][0].box)),
    "transit_clearance": lambda c: _pallets(c, transit_clearance_mm=11.0),
    "clearance": lambda c: replace(c, world=replace(c.world, clearance_mm=c.world.clearance_mm + 1.0)),
    "retreat": lambda c: replace(c, motion=replace(c.motion, retreat_mm=c.motion.retreat_mm + 1.0)),
    "start_tolerance": lambda c: replace(c, motion=replace(c.motion, start_tolerance_deg=1.5)),
    "minus_zero": lambda c: _pallets(c, overhang_mm=-0.0) if c.sections["pallet"][0].overhang_mm == 0.0 else None,
}


@pytest.mark.parametrize("field", sorted(READ))
def test_a_cell_that_differs_in_a_field_the_proofs_read_is_proven_anew(cell, field):
    """Its key differs from the cell's (the choice and the proofs are made again for it)."""
    mutant = READ[field](cell)
    if mutant is None:
        pytest.skip(f"{field}: the bundled cell has no such value to change")
    assert _key(mutant) != _key(cell)


def test_a_cell_that_differs_only_in_what_the_proofs_do_not_read_takes_the_same_key(cell):
    assert _key(_unread(cell)) == _key(cell)
    assert _key(replace(cell, sections=dict(cell.sections))) == _key(cell)  # another Cell object, equal values


def test_a_cycle_other_than_the_cells_takes_another_key(cell):
    cycle = full_cycle(cell, cell.sections["pallet"][0])
    assert _key(cell, cycle[:-1]) != _key(cell, cycle)


def test_a_kept_choice_is_the_one_made_anew(cell, monkeypatch):
    """The choice and proofs a cell of other speeds, masses, blending and timeout reuses are the ones worked out for it
    from nothing (no kept choice, no kept path proof): UNREAD names only fields they do not read. And the mutant's plan
    takes them without proving again (one kept choice, no new one)."""
    kind = cell.kinds["pallet"]
    kept = kind.plan(cell, TARGET).pallets[0]
    mutant = _unread(cell)
    real, made = posture.decide_anew, []
    monkeypatch.setattr(posture, "decide_anew", lambda *args: made.append(args) or real(*args))
    reused = kind.plan(mutant, TARGET).pallets[0]
    assert made == []
    monkeypatch.setattr(posture, "decide_anew", real)
    monkeypatch.setattr(posture, "DECIDED", Kept(64))
    monkeypatch.setattr(posture, "PROVEN", Kept(512))
    pallet = mutant.sections["pallet"][0]
    anew = posture.decide_anew(mutant, pallet, TARGET, tuple(full_cycle(mutant, pallet)))
    assert _value(anew) == _value((reused.named, reused.note, (reused.reach, reused.proven)))
    assert _value(anew) == _value((kept.named, kept.note, (kept.reach, kept.proven)))
    assert anew[2] is not None and len(posture.PROVEN.entries) > 0  # proven here, path by path


def test_a_path_proven_for_one_cell_is_kept_for_another_where_it_is_the_same_path(cell, monkeypatch):
    """Another retreat changes the way home after a stop (those paths are proven anew) and not the full cycle's path
    (its proof kept); a path's key changes with the path, the bar and what the proof reads of the cell."""
    from codegen.kinds.pallet.scene import pallet_paths
    from codegen.kinds.pallet.section import pallets_of
    from codegen.world import proof

    planned = cell.kinds["pallet"].plan(cell, TARGET).pallets[0]
    mutant = replace(cell, motion=replace(cell.motion, retreat_mm=cell.motion.retreat_mm + 1.0))
    pallet = mutant.sections["pallet"][0]
    paths = pallet_paths(mutant, pallets_of(mutant), pallet, TARGET, planned.named, full_cycle(mutant, pallet))
    real, proved = proof.prove, []

    def counted(cell, paths, *args):
        proved.extend(paths)
        return real(cell, paths, *args)

    monkeypatch.setattr(proof, "prove", counted)
    least = [posture.proven(mutant, path, None) for path in paths]
    assert all(p is not paths[0] for p in proved) and 0 < len(proved) < len(paths)
    assert least[0] is posture.proven(mutant, paths[0], None) and len(proved) < len(paths)
    key = posture.path_key(mutant, paths[0], None)[0]
    assert posture.path_key(mutant, paths[0], 1.0)[0] != key
    assert posture.path_key(mutant, replace(paths[0], moves=paths[0].moves[:-1]), None)[0] != key
    assert posture.path_key(READ["clearance"](mutant), paths[0], None)[0] != key
    assert posture.path_key(READ["tool_tcp"](mutant), paths[0], None)[0] != key
    assert posture.path_key(_pallets(mutant, name="other"), paths[0], None)[0] != key  # its solids' names


def test_the_stores_are_bounded():
    store = Kept(2)
    for i in range(3):
        store.put(bytes([i]), i, [])
    assert store.get(b"\x00") is None and store.get(b"\x01") == 1 and store.get(b"\x02") == 2
