"""The pallet kind's plan for a cell on one target: each pallet's cycle, configurations and proofs, worked out once."""

# The program writer, the reach and clearance proofs, verify's setup and judgement and the scene read this plan
# (codegen.protocol.Kind.plan hands it down with the cell) instead of working the full cycle and the posture out again.

from __future__ import annotations

from dataclasses import dataclass, replace

from codegen.kinds.pallet.kind import KIND
from codegen.kinds.pallet.posture import decide, reach_in
from codegen.kinds.pallet.reach import Named, PalletReach
from codegen.kinds.pallet.section import Pallet, pallets_of
from codegen.kinds.pallet.shape import full_cycle


@dataclass(frozen=True)
class PalletPlan:
    """One pallet on one target: the full cycle's moves (the reference's, stacking or unstacking from the first box),
    the configurations its program names (None without an arm), the posture note (generate's report; "": the
    controller's own), and the proofs the posture's choice made of them (None: not made yet; the proof runs where it
    is asked): the reach proof and the clearance proof's least clearances of the pallet's paths."""

    pallet: Pallet
    cycle: tuple
    named: Named | None
    note: str = ""
    reach: PalletReach | None = None
    proven: tuple | None = None


@dataclass(frozen=True)
class Plan:
    """The pallet kind's plan for one target: a PalletPlan per [[pallet]], in the cell file's order."""

    target: str
    pallets: tuple[PalletPlan, ...]

    def of(self, pallet: Pallet) -> PalletPlan:
        """The plan of one of the cell's pallets."""
        return next(p for p in self.pallets if p.pallet is pallet)


def plan(cell, target: str) -> Plan:
    """The kind's planner: each pallet's full cycle (the cell's, the same on every target: codegen/kinds/pallet/
    shape.py), then the configurations its program names on the target's arm (codegen/kinds/pallet/posture.py: the
    controller's own, the cell's [pallet.config], or a posture chosen to clear), with the proofs that choice made."""
    out = []
    for pallet in pallets_of(cell):
        cycle = full_cycle(cell, pallet)
        named, note, proofs = decide(cell, pallet, target, cycle)
        reach, proven = proofs if proofs is not None else (None, None)
        out.append(PalletPlan(pallet, cycle, named, note, reach, proven))
    return Plan(target, tuple(out))


def pallet_plan(cell, pallet: Pallet, target: str) -> PalletPlan:
    """The plan of one pallet of the cell on the target (the kind's plan, made once per cell and target)."""
    return KIND.plan(cell, target).of(pallet)


def configurations(cell, pallet: Pallet, target: str) -> Named | None:
    """The configurations the target's program names for the pallet (None without an arm): the program, the reach and
    clearance proofs and every verify case read them."""
    return pallet_plan(cell, pallet, target).named


def posture_note(cell, pallet: Pallet, target: str) -> str:
    """'' where the program names the configurations the controller takes from the home; else what was chosen and
    why (generate's report)."""
    return pallet_plan(cell, pallet, target).note


def check(cell, only: list[str] | None = None) -> list[PalletReach]:
    """The reach proof of every pallet on every target with an arm (of `only`, if given), in the configurations the
    program names, with the posture note where one was chosen: the plan's where its choice made it."""
    if cell.robot is None:
        return []
    targets = [t for t in cell.targets if t in cell.robot.arms and (only is None or t in only)]
    out = []
    for target in targets:
        for planned in KIND.plan(cell, target).pallets:
            proof = planned.reach or reach_in(cell, planned.pallet, target, planned.named, planned.cycle)
            out.append(replace(proof, posture=planned.note))
    return out
