"""Verify pallet programs: the kind's verify plan (its cases, their setup and judgement) and its figures."""

from __future__ import annotations

from dataclasses import dataclass

from codegen import protocol
from codegen.kinds.pallet.cases import SCENARIOS, verify_cases
from codegen.kinds.pallet.judge import judge
from codegen.kinds.pallet.section import pallets_of
from codegen.kinds.pallet.setup import setup


@dataclass
class PalletFigures(protocol.Figures):
    boxes: int = 0  # boxes placed (or taken) over the passing cases

    def count(self, case, judged: int) -> None:
        self.boxes += judged

    def as_json(self) -> dict:
        return {"boxes_placed": self.boxes}


class VerifyPart(protocol.VerifyPlan):
    """A pallet program's cases (a whole stack and its interruptions, each box's pose from the pallet's reference)."""

    report_key = "pallets"
    scenarios = SCENARIOS
    figures = PalletFigures
    listed = {  # a row as `codegen verify --json` lists it under "pallets"
        "target": "target",
        "pallet": "program",
        "files": "files",
        "cases": "cases",
        "mismatches": "mismatches",
        "boxes_placed": "boxes_placed",
        "pos_max_mm": "position_error_mm.max",
        "rot_max_deg": "orientation_error_deg.max",
        "cases_per_s": "cases_per_second",
        "first_mismatches": "first_mismatches",
    }

    def cases(self, cell, source, count: int, seed: int) -> list:
        return verify_cases(cell, source, seed)

    def setup(self, cell, source, case):
        return setup(cell, source, case)

    def judge(self, cell, source, case, trace, setup):
        return judge(cell, source, case, trace, setup)

    def describe(self, cell, case) -> str:
        run = case.data
        pallet = "" if run.pallet < 0 else f"pallet {pallets_of(cell)[run.pallet].name} "
        layer, box = run.case.layer, run.case.box
        if layer < 0:  # the counters as a stop in a release leaves them: the layer marked negative
            return f"{pallet}layer {-layer} box {box} (the counters marked: layer {layer})"
        return f"{pallet}layer {layer} box {box}"

    def report_lines(self, rows: list) -> list[str]:
        lines = ["pallet program          target    cases  fail  boxes"]
        for r in rows:
            boxes = 0 if r.figures is None else r.figures.boxes
            lines.append(f"{r.program[:23]:23} {r.target:8} {r.cases:6d} {r.mismatches:5d} {boxes:6d}")
        return lines
