"""Interpreter speed: verified cases per second per dialect, and the demo cell's full verify.

Goals (issue 4): >= 5,000 verified cases/s per dialect on this 2-core machine, parsing each program
once and running it many times; demo full verify (8 stations x 4 targets x 1,000 random readings
plus edge cases) <= 15 s wall.

A verified case is the reference trace (float64), the program run in the interpreter and the
comparison of the two. Measured per dialect on the demo cell with its edge-case station (the case
set of `codegen verify`), after the program is parsed and compiled once:
  - one core: one process, every case;
  - two cores: two worker processes, each with the program loaded, half of the cases each (wall
    time of the parallel part).
Each figure is the median and the best of --repeat runs (the machine is shared: expect spread).

Issue 16 measures the one-core rate against the same cases written by hand in Python (the reference,
the program's float32 math, the arm and the comparison without an interpreter: benchmarks/handwritten.py),
in the same run.

Run: python benchmarks/bench_verify.py [--repeat N] [--targets ur,kuka,...] [--no-full]
"""

from __future__ import annotations

import argparse
import multiprocessing
import statistics
import subprocess
import sys
import time

from record import Figures

FIGURES = Figures(__file__)

_STATE: dict = {}


def _load(target: str) -> None:
    """Worker initialiser: build the case set and load the program once."""
    from codegen.kinds.station.cases import build_cases, edge_cell
    from codegen.model.cell import load_cell
    from codegen.verify.programs import fresh_sources

    model = load_cell()
    cell = edge_cell(model) if model.robot is None else model  # with an arm the edge poses are verified apart
    source = next(s for s in fresh_sources(cell, [target]) if not s.ident.endswith("_node"))  # the station program
    source.load()
    _STATE.update(cell=cell, cases=build_cases(cell, 1000, 0), source=source)


def _verify_slice(args: tuple[str, int, int]) -> tuple[int, int]:
    """Verify cases[start::step] with the loaded program: (cases, mismatches)."""
    from codegen.dialects.core.machine import DEFAULT_STEP_LIMIT
    from codegen.verify.runner import run_cases

    _target, start, step = args
    cases = _STATE["cases"][start::step]
    row = run_cases(_STATE["cell"], _STATE["source"], cases, DEFAULT_STEP_LIMIT)
    return row.cases, row.mismatches


def one_core(target: str, repeat: int) -> list[float]:
    _load(target)
    rates = []
    for _ in range(repeat):
        start = time.perf_counter()
        count, mismatches = _verify_slice((target, 0, 1))
        rates.append(count / (time.perf_counter() - start))
        assert mismatches == 0, f"{target}: {mismatches} mismatches"
    return rates


def hand_written(target: str, repeat: int) -> list[float]:
    """The same cases by the hand-written yardstick (benchmarks/handwritten.py), one core, after one_core."""
    import handwritten

    rates = []
    for _ in range(repeat):
        start = time.perf_counter()
        problems = sum(handwritten.case(_STATE["cell"], target, one) is not None for one in _STATE["cases"])
        rates.append(len(_STATE["cases"]) / (time.perf_counter() - start))
        assert problems == 0, f"{target}: the hand-written case disagrees with the reference {problems} times"
    return rates


def two_cores(target: str, repeat: int) -> list[float]:
    context = multiprocessing.get_context("fork")
    rates = []
    with context.Pool(2, initializer=_load, initargs=(target,)) as pool:
        pool.map(_verify_slice, [(target, 0, 200), (target, 1, 200)])  # both workers loaded and warm
        for _ in range(repeat):
            start = time.perf_counter()
            results = pool.map(_verify_slice, [(target, 0, 2), (target, 1, 2)], chunksize=1)
            rates.append(sum(c for c, _ in results) / (time.perf_counter() - start))
            assert all(m == 0 for _, m in results), f"{target}: mismatches"
    return rates


def main() -> int:
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--targets", default="ur,kuka,abb,dtrans")
    parser.add_argument("--no-full", action="store_true", help="skip the full `codegen verify` run")
    args = parser.parse_args()
    FIGURES.line("verified cases/s per dialect (reference + interpreter + comparison), median / best; the same cases")
    FIGURES.line("by the hand-written yardstick (benchmarks/handwritten.py) on one core, and the ratio of the medians:")
    FIGURES.line(f"  {'target':<7} {'one core':>17} {'two cores':>17} {'hand-written':>17} {'ratio':>6}")
    for target in args.targets.split(","):
        one = one_core(target, args.repeat)
        hand = hand_written(target, args.repeat)
        two = two_cores(target, args.repeat)
        FIGURES.line(
            f"  {target:<7} {statistics.median(one):8.0f} / {max(one):6.0f} "
            f"{statistics.median(two):8.0f} / {max(two):6.0f} "
            f"{statistics.median(hand):8.0f} / {max(hand):6.0f} {statistics.median(one) / statistics.median(hand):6.2f}"
        )
    if args.no_full:
        return 0
    start = time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "codegen", "verify"], capture_output=True, text=True)
    wall = time.perf_counter() - start
    FIGURES.line(proc.stdout.strip())
    FIGURES.line(f"full `codegen verify` on the demo cell: {wall:.1f} s wall incl. start-up (goal <= 15 s)")
    return proc.returncode


if __name__ == "__main__":
    code = main()
    FIGURES.write()  # the figures into docs/benchmarks.md, dated, with the machine
    sys.exit(code)
