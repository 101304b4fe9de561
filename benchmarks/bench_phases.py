"""Where the demo cell's verify spends its CPU, by phase: cProfile (timed by the process's CPU clock) over one process.

Two passes over the bundled demo cell, every target, in this one process (no workers: process start and transfer
are not in it; the whole command's figures are measured apart, with /usr/bin/time):
  1. its cases (--cases per station, as `codegen verify --cases`), with the clearance sweeps, no bulk runs;
  2. the bulk runs of the station ids not in the cell alone (no cases; the programs are loaded by then).
Each phase is the cumulative CPU of the functions that make it (a function called inside another is counted in
both: the indented rows are parts of the row above them).

Run: python benchmarks/bench_phases.py [--cases N] [--no-write]
"""

from __future__ import annotations

import argparse
import cProfile
import pstats
import time

from record import Figures

FIGURES = Figures(__file__)

# (indent, what, the functions that make it: (file ending, function name)); in the pass named
PHASES = {
    "cases": [
        (0, "programs rendered, reach proved (engine.prepare)", [("verify/engine.py", "prepare")]),
        (0, "programs parsed and compiled (ProgramSource.load)", [("verify/programs.py", "load")]),
        (0, "the cases' interpreted runs (runner._run)", [("verify/runner.py", "_run")]),
        (1, "the arm's solutions in the interpreter (arm.resolve)", [("dialects/core/arm.py", "resolve")]),
        (0, "reference + judgement (the kind's setup and judge)", [("station/judge.py", "setup"),
                                                                   ("station/judge.py", "judge")]),
        (0, "the common checks (Checker.check)", [("verify/checks.py", "check")]),
        (1, "the arm's solutions by the controller's rule (expected_joints)", [("station/joints.py",
                                                                               "expected_joints")]),
        (0, "clearance sweeps (runner._clearance)", [("verify/runner.py", "_clearance")]),
    ],
    "bulk": [
        (0, "bulk ids: the runs chosen by class (station sweep)", [("station/judge.py", "sweep")]),
        (1, "the choice of ids (codegen/verify/bulk.py)", [("verify/bulk.py", "representatives")]),
    ],
}


def _cumulative(stats: pstats.Stats, functions: list[tuple[str, str]]) -> tuple[int, float]:
    """Calls and cumulative seconds of the functions named (a method and a module function of one name in one
    file: the outermost, the largest)."""
    calls, seconds = 0, 0.0
    for suffix, name in functions:
        found = [(nc, ct) for (file, _, func), (_, nc, _, ct, _) in stats.stats.items()
                 if func == name and file.endswith(suffix)]
        if found:
            nc, ct = max(found, key=lambda f: f[1])
            calls, seconds = calls + nc, seconds + ct
    return calls, seconds


def _profiled(options) -> tuple[pstats.Stats, float, float, object]:
    from codegen.model.cell import load_cell
    from codegen.verify.engine import verify_cell

    cell = load_cell()
    profile = cProfile.Profile(time.process_time)
    wall, cpu = time.perf_counter(), time.process_time()
    report = profile.runcall(verify_cell, cell, (), (), options)
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    return pstats.Stats(profile), wall, cpu, report


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", type=int, default=100)
    parser.add_argument("--no-write", action="store_true", help="print only; docs/benchmarks.md unchanged")
    args = parser.parse_args()

    from codegen.verify.engine import Options

    with open("/proc/loadavg", encoding="utf-8") as f:
        FIGURES.line(f"load average at the start: {' '.join(f.read().split()[:3])} (1, 5, 15 min)")
    passes = {
        "cases": Options(cases=args.cases, jobs=1, sweeps=False),
        "bulk": Options(cases=args.cases, jobs=1, sweeps=True, scenarios=frozenset()),
    }
    total_cpu = 0.0
    results = {}
    for name, options in passes.items():
        stats, wall, cpu, report = _profiled(options)
        results[name] = (stats, wall, cpu, report)
        total_cpu += cpu
    FIGURES.line(f"{'phase (CPU under the profiler, one process)':<66} {'calls':>8} {'CPU s':>8} {'share':>6}")
    for name, (stats, wall, cpu, report) in results.items():
        runs = sum(r.cases for r in report.rows)
        swept = sum(r.swept for r in report.rows)
        ran = sum(r.bulk_run for r in report.rows)
        what = f"{runs} runs of the cases" if name == "cases" else f"{swept} bulk ids, {ran} run"
        FIGURES.line(f"pass {name}: {what}; {cpu:.1f} s CPU, {wall:.1f} s wall, "
                     f"{'ok' if report.ok else 'MISMATCHES'}")
        for indent, label, functions in PHASES[name]:
            calls, seconds = _cumulative(stats, functions)
            FIGURES.line(f"{'  ' * (indent + 1) + label:<66} {calls:>8} {seconds:>8.2f} "
                         f"{100 * seconds / total_cpu:>5.1f}%")
    FIGURES.line(f"{'both passes':<66} {'':>8} {total_cpu:>8.2f} {100.0:>5.1f}%")
    if not args.no_write:
        FIGURES.write()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
