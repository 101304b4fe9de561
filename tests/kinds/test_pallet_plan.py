"""The pallet kind's plan: made once per cell and target, handed down with the cell, its paths proved once."""

from __future__ import annotations

from dataclasses import replace

from support.cells import EXAMPLES

from codegen import generate
from codegen.model.cell import load_cell
from codegen.world import proof

TESTMAT = EXAMPLES["testmat_pallet"]


def test_the_plan_is_made_once_per_cell_and_target():
    cell = load_cell(TESTMAT)
    kind = cell.kinds["pallet"]
    kuka = kind.plan(cell, "kuka")
    assert kind.plan(cell, "kuka") is kuka
    assert kind.plan(cell, "abb") is not kuka and kind.plan(cell, "abb").target == "abb"
    assert [p.pallet for p in kuka.pallets] == list(cell.sections["pallet"])
    changed = replace(cell, sections=dict(cell.sections))  # another cell: its own plans, none inherited
    assert changed.plans == {} and kind.plan(changed, "kuka") is not kuka


def test_generate_takes_the_pallet_paths_as_the_posture_choice_proved_them(monkeypatch):
    """The posture's choice proved the pallet's paths (the plan keeps the least clearances): generate's clearance proof
    proves none of them again, and its least clearances are those of a proof of the same paths made here."""
    cell = load_cell(TESTMAT)
    target = "kuka"
    kind = cell.kinds["pallet"]
    paths = kind.scene.paths(cell, [target])
    assert paths and all(p.proven is not None for p in kind.plan(cell, target).pallets)
    fresh = proof.prove(cell, paths)
    real, proved = proof.prove, []

    def counted(cell, paths, *args, **kwargs):
        proved.extend(paths)
        return real(cell, paths, *args, **kwargs)

    monkeypatch.setattr(proof, "prove", counted)
    least = generate._proven(cell, target)
    assert proved == []  # no path proven a second time
    assert [(x.where, x.found.distance) for x in least] == [(x.where, x.found.distance) for x in fresh]
