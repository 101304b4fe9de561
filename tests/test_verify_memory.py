"""A large cell's verify holds one target's program per worker at a time: the same reports as all at once."""

from __future__ import annotations

from codegen import verify_runs
from codegen.model.cell import load_cell
from codegen.verify import build_cases
from codegen.verify_runs import fresh_sources, run_verify

DEMO = "codegen/examples/agv_machine_tending.toml"


def _summaries(reports):
    return [
        {k: v for k, v in r.summary().items() if k not in ("seconds", "cases_per_second")} for r in reports
    ]


def test_one_target_at_a_time_gives_the_reports_of_all_at_once(monkeypatch):
    """The demo cell treated as large (ONE_PROGRAM_FROM = 1): the tasks go target by target, each worker
    lets a program go when the next target's task comes, and every target's report (cases, mismatches,
    halts, errors) is the one the tasks over all targets give (the id sweep, the same path, is left out: time)."""
    cell = load_cell(DEMO)
    sources = fresh_sources(cell, list(cell.targets))
    cases = build_cases(cell, 2, 0)
    together = run_verify(cell, sources, cases, 1, None, cell, sweep=False)
    verify_runs._LOADED.clear()
    monkeypatch.setattr(verify_runs, "ONE_PROGRAM_FROM", 1)
    apart = run_verify(cell, sources, cases, 1, None, cell, sweep=False)
    assert _summaries(apart) == _summaries(together)
    assert len(verify_runs._LOADED) == 1  # the last target's program only


def test_targets_pinned_to_workers_give_the_same_reports(monkeypatch):
    """As many targets as workers or more (a large cell): each worker process runs whole targets, loading
    each program once; the reports, in the targets' order, are those of one process, and progress counts
    every case."""
    cell = load_cell(DEMO)
    sources = fresh_sources(cell, ["ur", "kuka", "abb"])
    cases = build_cases(cell, 1, 0)
    alone = run_verify(cell, sources, cases, 1, None, cell, sweep=False)
    monkeypatch.setattr(verify_runs, "CHUNK_CASES", 40)  # several chunks per target
    monkeypatch.setattr(verify_runs, "ONE_PROGRAM_FROM", 1)
    counted = []
    pinned = run_verify(cell, sources, cases, 2, counted.append, cell, sweep=False)
    assert [r.target for r in pinned] == ["ur", "kuka", "abb"]
    assert _summaries(pinned) == _summaries(alone)
    assert sum(counted) == 3 * len(cases)


def test_the_heap_is_frozen_only_while_cases_run():
    """verify keeps Python's full collections off what was alive when it began (the loaded program) while
    its cases run, and gives it back to the collector when it ends, also when a run raises."""
    import gc

    import pytest

    from codegen.verify import verify
    from codegen.verify_runs import fresh_programs

    cell = load_cell(DEMO)
    programs = fresh_programs(cell, ["ur"])
    cases = build_cases(cell, 1, 0)[:5]
    frozen = []
    verify(cell, ["ur"], programs, cases, progress=lambda n: frozen.append(gc.get_freeze_count()))
    assert frozen and min(frozen) > 1000
    assert gc.get_freeze_count() == 0

    def fail(_):
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        verify(cell, ["ur"], programs, cases, progress=fail)
    assert gc.get_freeze_count() == 0
