"""The pallet kind's scene part: its drawing, its solids, and the paths generate proves, in the configurations its
programs name."""

from __future__ import annotations

from codegen import protocol
from codegen.kinds.pallet.plan import pallet_plan
from codegen.kinds.pallet.scene import carried_box, case_stages, objects, pallet_paths, solids
from codegen.world.proof import Path
from codegen.world.solids import Box


class ScenePart(protocol.Scene):
    def objects(self, cell) -> list[dict]:
        return objects(cell, self.kind.section.of(cell) or ())

    def solids(self, cell) -> dict[str, Box]:
        return solids(cell, self.kind.section.of(cell) or ())

    def paths(self, cell, targets: list[str]) -> list[Path]:
        pallets = self.kind.section.of(cell) or ()
        if cell.robot is None:
            return []
        out = []
        for target in [t for t in targets if t in cell.robot.arms]:
            for pallet in pallets:
                planned = pallet_plan(cell, pallet, target)
                out += pallet_paths(cell, pallets, pallet, target, planned.named, planned.cycle)
        return out

    def proven(self, cell, target: str) -> list | None:
        """Each pallet's paths as the posture's choice proved them (the plan's), the others proven here."""
        from codegen.world.proof import prove  # coal: loaded only when proving

        pallets = self.kind.section.of(cell) or ()
        if cell.robot is None or target not in cell.robot.arms:
            return []
        out = []
        for pallet in pallets:
            planned = pallet_plan(cell, pallet, target)
            if planned.proven is not None:
                out += planned.proven
            else:
                out += prove(cell, pallet_paths(cell, pallets, pallet, target, planned.named, planned.cycle))
        return out

    def carried(self, cell):
        """The first pallet's box (a task of several pallets: each case's own in staged)."""
        pallets = self.kind.section.of(cell) or ()
        return None if not pallets or cell.robot is None else carried_box(cell, pallets[0])

    def staged(self, cell, target: str, case):
        pallets = self.kind.section.of(cell) or ()
        run = getattr(case, "data", None)
        index = getattr(run, "pallet", -1)
        if not pallets or cell.robot is None or index < 0:  # a task whose pallets are all off stops before a move
            return super().staged(cell, target, case)
        return case_stages(cell, pallets, index, run.case)
