"""A large cell's verify holds one program per worker at a time: the same rows as all at once; the heap is frozen
only while a program's cases run."""

from __future__ import annotations

import gc

import pytest

from codegen.kinds.station.cases import build_cases
from codegen.model.cell import load_cell
from codegen.verify import engine, runner
from codegen.verify.engine import Options, verify_sources
from codegen.verify.programs import fresh_sources

DEMO = "codegen/examples/agv_machine_tending.toml"


TIMES = ("seconds", "cases_per_second", "clearance_seconds")


def _summaries(rows):
    return [{k: v for k, v in r.summary().items() if k not in TIMES} for r in rows]


def _same_rows(got, want) -> None:
    """Row by row, naming the keys that differ."""
    assert len(got) == len(want)
    for a, b in zip(_summaries(got), _summaries(want), strict=True):
        assert a == b, {k: (a.get(k), b.get(k)) for k in {*a, *b} if a.get(k) != b.get(k)}


@pytest.mark.slow
def test_one_program_at_a_time_gives_the_rows_of_all_at_once(monkeypatch):
    """The demo cell treated as large (ONE_PROGRAM_FROM = 1): a worker lets a program go when the next
    program's task comes, and every row (cases, mismatches, halts, errors) is the one of the tasks over all
    programs (the id sweep, the same path, is left out: time)."""
    cell = load_cell(DEMO)
    sources = fresh_sources(cell, list(cell.targets))
    options = Options(cases=2, jobs=1, sweeps=False)
    together, _ = verify_sources(cell, sources, options)
    runner._LOADED.clear()
    monkeypatch.setattr(runner, "ONE_PROGRAM_FROM", 1)
    apart, _ = verify_sources(cell, sources, options)
    _same_rows(apart, together)
    assert len(runner._LOADED) == 1  # the last program only


@pytest.mark.slow
def test_programs_pinned_to_workers_give_the_same_rows(monkeypatch):
    """As many programs as workers or more (a large cell): each worker process runs whole programs, loading
    each once; the rows, in the programs' order, are those of one process, and progress counts every case."""
    cell = load_cell(DEMO)
    sources = [s for s in fresh_sources(cell, ["ur", "kuka", "abb"]) if not s.ident.endswith("_node")]
    alone, _ = verify_sources(cell, sources, Options(cases=1, jobs=1, sweeps=False))
    monkeypatch.setattr(engine, "CHUNK_CASES", 40)  # several chunks per program
    monkeypatch.setattr(runner, "ONE_PROGRAM_FROM", 1)
    counted = []
    pinned, _ = verify_sources(cell, sources, Options(cases=1, jobs=2, progress=counted.append, sweeps=False))
    assert [r.target for r in pinned] == ["ur", "kuka", "abb"]
    _same_rows(pinned, alone)
    assert sum(counted) == sum(r.cases for r in alone)


def test_the_heap_is_frozen_only_while_cases_run(monkeypatch):
    """verify keeps Python's full collections off what was alive when it began (the loaded program) while its
    cases run, and gives it back to the collector when they end, also when a run raises."""
    cell = load_cell(DEMO)
    (source,) = [s for s in fresh_sources(cell, ["ur"]) if not s.ident.endswith("_node")]
    cases = build_cases(cell, 1, 0)[:5]
    kind = cell.kinds[source.kind].verify
    judge, frozen = kind.judge, []

    def watched(*args):
        frozen.append(gc.get_freeze_count())
        return judge(*args)

    monkeypatch.setattr(kind, "judge", watched)
    runner.run_cases(cell, source, cases, 200_000)
    assert frozen and min(frozen) > 1000
    assert gc.get_freeze_count() == 0

    def fail(*_args):
        raise KeyboardInterrupt

    monkeypatch.setattr(kind, "judge", fail)
    with pytest.raises(KeyboardInterrupt):
        runner.run_cases(cell, source, cases, 200_000)
    assert gc.get_freeze_count() == 0
