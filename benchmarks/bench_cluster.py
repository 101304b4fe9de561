"""Verify spread over workers: cells/s and cases/s for 1 and 2 workers, local processes and a Dask cluster, the
per-task overhead, and a model of a 500-cell plant on N workers.

The plant measured is every example cell (codegen/examples) on one target each (its last), verified with
--cases random readings per station and no bulk runs, through verify_cells: one task per cell for its programs,
then the case batches of all cells. The Dask cluster is a distributed.LocalCluster of N worker processes of one
thread each, on this machine; its start-up is timed apart. The per-task overhead is the wall time of --tasks
empty tasks divided by their number (two workers), and the bytes one case-batch task sends.

Model of a plant of P cells on N workers: T(N) = start + P * w / (N * e) + P * k * o, where w is a cell's work on
one worker (seconds, measured), e the efficiency from 1 to 2 workers (measured), k the tasks per cell and o the
per-task overhead (the scheduler hands tasks out one after another, so this term does not shrink with N).

Run: python benchmarks/bench_cluster.py [--cases N] [--tasks N] [--plant P]
"""

from __future__ import annotations

import argparse
import os
import pickle
import time

from record import Figures

FIGURES = Figures(__file__)


def _cells():
    from codegen.model.cell import EXAMPLES_DIR, load_cell
    from codegen.verify.engine import CellRun

    runs = []
    for path in sorted(EXAMPLES_DIR.rglob("*.toml")):
        cell = load_cell(path)
        runs.append(CellRun(cell, (), (cell.targets[-1],)))
    return runs


def _plant(runs, executor, cases: int) -> tuple[float, int, int]:
    """verify_cells of the runs: (wall seconds, cases run, tasks sent)."""
    from codegen.verify.engine import Options, verify_cells

    counted = _Counting(executor)
    start = time.perf_counter()
    reports = verify_cells(runs, Options(cases=cases, sweeps=False, executor=counted))
    wall = time.perf_counter() - start
    bad = [r for r in reports if isinstance(r, Exception) or not r.ok]
    assert not bad, bad
    return wall, sum(row.cases for report in reports for row in report.rows), counted.tasks


class _Counting:
    """An executor that counts the tasks it is given."""

    def __init__(self, executor) -> None:
        self.executor, self.workers, self.tasks = executor, executor.workers, 0

    def map(self, fn, tasks, groups=None):
        self.tasks += len(tasks)
        return self.executor.map(fn, tasks, groups)


def _overhead(executor, count: int) -> float:
    """Seconds per empty task through the executor."""
    start = time.perf_counter()
    results = list(executor.map(abs, list(range(count))))
    assert results == list(range(count))
    return (time.perf_counter() - start) / count


def _task_bytes(runs, cases: int) -> int:
    """The pickled size of a case batch of the first cell (what a worker is sent per task)."""
    from codegen.verify.engine import Options, _fresh, _tasks

    cell = runs[0].cell
    tasks, _ = _tasks(cell, _fresh(cell, list(runs[0].targets)), Options(cases=cases), 2)
    return max(len(pickle.dumps(task)) for task in tasks)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", type=int, default=10, help="random readings per station")
    parser.add_argument("--tasks", type=int, default=400, help="empty tasks for the overhead")
    parser.add_argument("--plant", type=int, default=500, help="cells of the modelled plant")
    args = parser.parse_args()

    from distributed import Client, LocalCluster

    from codegen.plant.executors import DaskExecutor, LocalExecutor

    runs = _cells()
    load = os.getloadavg()
    FIGURES.line(f"load average at the start: {load[0]:.1f} {load[1]:.1f} {load[2]:.1f} (1, 5, 15 min) on 2 cores")
    FIGURES.line(f"plant: {len(runs)} example cells, one target each, --cases {args.cases}, no bulk runs")
    FIGURES.line(
        f"{'where':<22}{'workers':>8}{'start s':>9}{'wall s':>9}{'cells/s':>9}{'cases/s':>9}{'tasks':>7}"
        f"{'overhead ms/task':>18}"
    )
    measured = {}
    for workers in (1, 2):
        local = LocalExecutor(workers)
        wall, cases, tasks = _plant(runs, local, args.cases)
        over = _overhead(local, args.tasks) if workers > 1 else 0.0
        measured[("local", workers)] = (0.0, wall, cases, tasks, over)
        start = time.perf_counter()
        with (
            LocalCluster(
                n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None, silence_logs=50
            ) as cluster,
            Client(cluster, set_as_default=False) as client,
            DaskExecutor(client) as dask,
        ):
            client.wait_for_workers(workers)
            started = time.perf_counter() - start
            wall, cases, tasks = _plant(runs, dask, args.cases)
            over = _overhead(dask, args.tasks)
        measured[("dask", workers)] = (started, wall, cases, tasks, over)
        for where in ("local", "dask"):
            started, wall, cases, tasks, over = measured[(where, workers)]
            name = "local processes" if where == "local" else "Dask LocalCluster"
            over_text = f"{over * 1000:.2f}" if over else "-"
            FIGURES.line(
                f"{name:<22}{workers:>8}{started:>9.1f}{wall:>9.1f}{len(runs) / wall:>9.3f}"
                f"{cases / wall:>9.0f}{tasks:>7}{over_text:>18}"
            )
    FIGURES.line(f"a case-batch task sends {_task_bytes(runs, args.cases) / 1024:.0f} KiB (cell, program text, cases)")
    FIGURES.line(f"load average at the end: {' '.join(f'{x:.1f}' for x in os.getloadavg())}")

    started, one, _cases, tasks, _ = measured[("dask", 1)]
    two = measured[("dask", 2)][1]
    per_cell = one / len(runs)
    efficiency = min(1.0, one / (2 * two))
    per_task = measured[("dask", 2)][4]
    k = tasks / len(runs)
    FIGURES.line(
        f"model, {args.plant} cells on N Dask workers: w = {per_cell:.1f} s a cell on one worker, e = {efficiency:.2f}"
        f" (1 -> 2 workers), k = {k:.1f} tasks a cell, o = {per_task * 1000:.2f} ms a task, start = {started:.1f} s"
    )
    for n in (1, 2, 8, 32, 128):
        total = started + args.plant * per_cell / (n * (efficiency if n > 1 else 1.0)) + args.plant * k * per_task
        FIGURES.line(f"  N = {n:>3}: {total / 60:8.1f} min")
    FIGURES.write()


if __name__ == "__main__":
    main()
