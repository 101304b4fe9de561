"""Clearance proofs kept by the value of what they read (codegen/world/kept.py): a change to each value read proves
again, a change to anything else does not, a refusal is never kept, the store is bounded."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from codegen import generate
from codegen.model.cell import load_cell
from codegen.world import kept
from codegen.world.proof import ClearanceError, prove

BELT = "codegen/examples/conveyor/belt_pick.toml"
LASER = "codegen/examples/laser/laser_tcp.toml"


@pytest.fixture
def proofs(monkeypatch) -> list:
    """The proofs worked out (each call of prove) in a store empty at the start."""
    made = []

    def counted(cell, paths, *args):
        made.append(len(paths))
        return prove(cell, paths, *args)

    monkeypatch.setattr(kept, "PROVEN", kept.Kept(128))
    monkeypatch.setattr(kept, "prove", counted)
    return made


def _paths(cell, kind: str, target: str = "ur"):
    return cell.kinds[kind].scene.paths(cell, [target])


def _robot(cell, **changes):
    return replace(cell, robot=replace(cell.robot, **changes))


def _tool(cell, **changes):
    return _robot(cell, tool=replace(cell.robot.tool, **changes))


def _pick(cell, **changes):
    section = cell.sections["conveyor"]
    picked = replace(section, pick=replace(section.pick, **changes))
    return replace(cell, sections={**cell.sections, "conveyor": picked})


def _raised_tcp(cell):
    tcp2flange = cell.robot.tool.tcp2flange.copy()
    tcp2flange[2, 3] += 1.0
    return _tool(cell, tcp2flange=tcp2flange)


def _arm_limits(cell):
    arm = cell.robot.arms["ur"]
    limits = tuple((lo + 1.0, hi) for lo, hi in arm.limits_deg)
    return _robot(cell, arms={**cell.robot.arms, "ur": replace(arm, limits_deg=limits)})


def _window(cell):
    start, end = cell.sections["conveyor"].pick.window_mm
    return _pick(cell, window_mm=(start + 10.0, end))


READ = {
    "clearance": lambda c: replace(c, world=replace(c.world, clearance_mm=c.world.clearance_mm - 1.0)),
    "floor (a solid)": lambda c: replace(c, world=replace(c.world, floor_z_mm=c.world.floor_z_mm - 1.0)),
    "arm": _arm_limits,
    "tcp": _raised_tcp,
    "tool shape": lambda c: _tool(c, radius_mm=c.robot.tool.radius_mm + 1.0),
    "the paths (the window)": _window,
}
UNREAD = {
    "tool mass": lambda c: _tool(c, mass_kg=c.robot.tool.mass_kg + 1.0),
    "speed": lambda c: replace(c, motion=replace(c.motion, speed_mm_s=c.motion.speed_mm_s + 1.0)),
    "file": lambda c: replace(c, source="elsewhere.toml", sha256="0" * 64),
    "no-part timeout": lambda c: _pick(c, no_part_s=c.sections["conveyor"].pick.no_part_s + 1.0),
}


def test_a_cell_loaded_again_reuses_the_proof_and_it_equals_a_fresh_one(proofs):
    first = kept.proven(load_cell(BELT), _paths(load_cell(BELT), "conveyor"))
    again_cell = load_cell(BELT)
    again = kept.proven(again_cell, _paths(again_cell, "conveyor"))
    assert proofs == [len(first)] and len(first) > 0
    assert again == first == prove(again_cell, _paths(again_cell, "conveyor"))


@pytest.mark.parametrize("change", sorted(READ))
def test_a_change_to_a_value_the_proof_reads_proves_again(proofs, change):
    cell = load_cell(BELT)
    kept.proven(cell, _paths(cell, "conveyor"))
    changed = READ[change](cell)
    paths = _paths(changed, "conveyor")
    assert kept.proof_key(changed, paths)[0] != kept.proof_key(cell, _paths(cell, "conveyor"))[0]
    assert kept.proven(changed, paths) == prove(changed, paths)
    assert len(proofs) == 2


@pytest.mark.parametrize("change", sorted(UNREAD))
def test_a_change_to_what_the_proof_does_not_read_keeps_it(proofs, change):
    cell = load_cell(BELT)
    kept.proven(cell, _paths(cell, "conveyor"))
    changed = UNREAD[change](cell)
    kept.proven(changed, _paths(changed, "conveyor"))
    assert len(proofs) == 1


def test_each_target_and_each_kind_has_its_own_proof(proofs):
    belt, laser = load_cell(BELT), load_cell(LASER)
    for target in ("ur", "kuka"):
        kept.proven(belt, _paths(belt, "conveyor", target))
        kept.proven(laser, _paths(laser, "laser", target))
    assert len(proofs) == 4


def test_a_refusal_is_not_kept(proofs):
    cell = load_cell(BELT)
    tight = replace(cell, world=replace(cell.world, clearance_mm=10_000.0))
    for _ in range(2):
        with pytest.raises(ClearanceError):
            kept.proven(tight, _paths(tight, "conveyor"))
    assert len(proofs) == 2 and not kept.PROVEN.entries


def test_the_store_drops_the_least_recently_used_beyond_its_size():
    store = kept.Kept(2)
    for key in (b"a", b"b"):
        store.put(key, key.upper(), [])
    assert store.get(b"a") == b"A"  # b is now the least recently used
    store.put(b"c", b"C", [])
    assert store.get(b"b") is None and store.get(b"a") == b"A" and store.get(b"c") == b"C"


def test_values_alike_but_not_equal_have_different_keys():
    assert kept.digest(0.0)[0] != kept.digest(-0.0)[0]
    assert kept.digest(np.zeros(3))[0] != kept.digest(np.zeros(3, dtype=np.float32))[0]
    assert kept.digest((1.0, 2.0))[0] != kept.digest([1.0, 2.0])[0]


def test_generate_keeps_a_kinds_proof_that_its_plan_does_not(proofs):
    generate._proven(load_cell(BELT), "ur")
    done = len(proofs)
    generate._proven(load_cell(BELT), "ur")
    assert done > 0 and len(proofs) == done


def test_the_digest_is_of_the_values_not_of_which_objects_are_shared():
    """Equal values give one digest whether the tree shares an object or holds equal copies: a digest of pickle's
    bytes did not (it writes an object met twice as a reference to the first), so a kept choice was missed after
    other work had shared a move's name or array with another (a test that passed alone failed after another)."""
    from codegen.kept import digest

    name = "layer 1 box 1 entry"
    shared = (name, name, np.arange(3.0))
    copies = ("layer 1 box 1 entry", "".join(["layer 1 box ", "1 entry"]), np.arange(3.0))
    assert shared[0] is shared[1] and copies[0] is not copies[1]
    assert digest(shared)[0] == digest(copies)[0]
    row = (1.5, 2.5)
    assert digest([row, row])[0] == digest([(1.5, 2.5), (1.5, 2.5)])[0]
