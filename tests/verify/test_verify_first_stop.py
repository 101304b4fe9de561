"""verify stopped at a program's first mismatch: the case that has the problem is not swept among the cell's solids
(its answer is known), the passing cases before it are."""

from __future__ import annotations

from support.cells import example
from support.programs import edited, regex_edit, sources, verify_one

from codegen.verify import clearance

# station 2 puts the part back in the chuck at the taught pose, not the corrected one: its cases with a shifted mark
# fail, the other stations' pass
UNCORRECTED = (r"^    movel\(pose_trans\(corr, p2_chuck\), ", "    movel(p2_chuck, ")
RANDOM = frozenset({"random"})


def test_the_failing_case_is_not_swept_when_verify_stops_there():
    cell = example("agv_machine_tending")
    source = sources(cell, "ur", "station")[0]
    mutant = edited(source, regex_edit(*UNCORRECTED), "uncorrected")
    row = verify_one(cell, mutant, cases=4, first_mismatch=True, scenarios=RANDOM)
    assert row.mismatches == 1 and "station 2 " in row.first_mismatches[0], row.first_mismatches
    plan = cell.kinds["station"].verify
    cases = [c for c in plan.cases(cell, source, 4, 0) if plan.scenario_of(c) in RANDOM]  # as the engine has them
    chosen = clearance.selected([c.category for c in cases], [plan.scenario_of(c) for c in cases])[: row.cases]
    assert chosen[-1], "the failing case is one verify would sweep (else this test shows nothing)"
    assert row.clearance_traces == sum(chosen[:-1])  # the passing cases swept as ever, the failing one not
