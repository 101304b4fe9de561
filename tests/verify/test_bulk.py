"""The bulk runs of the station ids chosen by class (codegen/verify/bulk.py): every behaviour a program's checks of
the id give is run at least once, and an edit that mishandles one id anywhere in the barcode range still fails."""

from __future__ import annotations

import operator

import pytest
from support import stations
from support.cells import example, replace_once

from codegen.kinds.station.keys import STATION_ID_MAX
from codegen.kinds.station.section import stations_of
from codegen.verify import bulk

IDS = range(STATION_ID_MAX + 1)
OPS = {"==": operator.eq, "!=": operator.ne, "<": operator.lt, "<=": operator.le, ">": operator.gt, ">=": operator.ge}
# checks of the id as a program writes them, each number in another notation
CHECKS = [("==", "20000", 20000), ("<", "'H7FF0'", 0x7FF0), (">", "1.2345E3", 1234.5), ("<=", "0x1F", 0x1F),
          (">=", "9.5", 9.5), ("!=", "7", 7), ("==", ".5e4", 5000)]


def test_every_path_through_the_checks_is_run():
    """Each id's answers to every check of a program's text: each distinct set of answers (a path) has a run."""
    text = "\n".join(f"  elif station_id {op} {written}:" for op, written, _ in CHECKS)
    chosen = set(bulk.representatives([text], IDS, sample=0))
    paths: dict[tuple, list[int]] = {}
    for i in IDS:
        paths.setdefault(tuple(OPS[op](i, value) for op, _, value in CHECKS), []).append(i)
    assert len(paths) > len(CHECKS)
    missed = [ids[0] for ids in paths.values() if chosen.isdisjoint(ids)]
    assert missed == [], f"paths without a run, e.g. the id {missed[:5]}"
    assert len(chosen) < len(IDS) // 100  # and it is a small part of the range


def test_the_printed_id_and_the_sample():
    """The id's digit count cuts the classes (the program prints the id); the sample is the same for the same
    text (every worker of a run sees the same ids) and other ids for another text."""
    chosen = set(bulk.representatives([""], IDS, sample=0))
    assert {9, 10, 99, 100, 999, 1000, 9999, 10000, 0, STATION_ID_MAX} <= chosen
    a, b = bulk.representatives(["x"], IDS), bulk.representatives(["y"], IDS)
    assert a == bulk.representatives(["x"], IDS) and a != b and len(a) - len(chosen) >= bulk.SAMPLE - 10


MUTANTS = {  # an id handled as a station's (the robot moves on a misread barcode), in each target's words
    "ur": ("  elif station_id == 2:", "  elif station_id == {id}:\n    st_lathe_1()\n  elif station_id == 2:"),
    "kuka": ("  CASE 1\n", "  CASE 1, {id}\n"),
}


@pytest.mark.parametrize("target", sorted(MUTANTS))
@pytest.mark.parametrize("extra", [20000, 8, 32767, 12345])
def test_an_id_handled_as_a_station_fails_among_the_few_ids_run(target, extra):
    cell = example("agv_machine_tending")
    text, dat = stations.files(cell, target)
    old, new = MUTANTS[target]
    mutant = stations.source(cell, target, replace_once(text, old, new.format(id=extra)), dat)
    row = stations.sweep(cell, mutant, IDS)
    assert row.swept == len(IDS) - len(stations_of(cell))  # every id that is not a station is counted
    assert row.bulk_run < row.swept // 20  # a few of them run
    assert row.mismatches == 1 and f"unknown station id {extra}:" in row.first_mismatches[0], row.first_mismatches


def test_the_report_counts_the_ids_shown_and_run():
    """The ids that are not stations are counted whole (bulk_runs, the station rows' unknown_ids_checked), the ids
    run beside them (bulk_ids_run, unknown_ids_run), in two workers' pieces of the range as in one."""
    from codegen.verify.engine import Options, verify_cell

    cell = example("agv_machine_tending")
    options = Options(cases=1, jobs=2, sweeps=True, scenarios=frozenset(), clearance=False)
    report = verify_cell(cell, targets=("kuka",), options=options)
    data = report.as_json()
    (row,) = [r for r in data["targets"] if r["bulk_runs"]]
    assert row["unknown_ids_checked"] == row["bulk_runs"] == len(IDS) - len(stations_of(cell))
    # every file of the program, as verify reads them (the .src, its .dat, the channel's configuration)
    texts = [f.text for f in stations.source(cell, "kuka").files]
    chosen = set(bulk.representatives(texts, IDS)) - {s.id for s in stations_of(cell)}
    assert row["unknown_ids_run"] == row["bulk_ids_run"] == len(chosen)
    assert f"{row['bulk_runs']} bulk ids ({len(chosen)} run)" in "\n".join(report.lines())
