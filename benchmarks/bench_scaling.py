"""How verify scales with the cell's size (issue 16): cases/s, program load time and memory per station count.

For each cell size (benchmarks/bench_render.py's cell: no arm, two poses a station) and each target, in a
fresh process: render the program, parse and compile it (the load time), then verify the same number of
random readings spread over the stations on one core, twice (cases/s: reference, interpreter run and
comparison; the first pass also compiles each station's code on its first use, the second is warm), and
report the process's peak memory. The issue's goal: cases/s within 20 % from 8 to 5,000 stations, and
verify's peak memory for 1,000 stations under 500 MB with two workers (this measures one process).

Run: python benchmarks/bench_scaling.py [--sizes 8,100,1000] [--cases 2000] [--targets ur,kuka,abb,dtrans]
(5,000 stations: add it to --sizes; its load takes minutes.)
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

from record import Figures

FIGURES = Figures(__file__)

CHILD = r"""
import json, random, resource, sys, time
from pathlib import Path
sys.path.insert(0, {bench!r})
from bench_render import make_cell
from codegen.dialects.core.machine import DEFAULT_STEP_LIMIT
from codegen.kinds.station.cases import build_cases
from codegen.model.cell import load_cell
from codegen.verify.programs import fresh_sources
from codegen.verify.runner import run_cases

stations, target, count, folder = {stations}, {target!r}, {cases}, Path({folder!r})
path = folder / "cell.toml"
path.write_text(make_cell(stations), encoding="utf-8")
cell = load_cell(path)
start = time.perf_counter()
source = next(s for s in fresh_sources(cell, [target]) if not s.ident.endswith("_node"))
program = source.load()
load_s = time.perf_counter() - start
cases = build_cases(cell, max(1, -(-count // stations)), 0)
cases = random.Random(0).sample(cases, min(count, len(cases)))
start = time.perf_counter()
first = run_cases(cell, source, cases, DEFAULT_STEP_LIMIT)  # the first pass compiles each station's code on first use
first_s = time.perf_counter() - start
start = time.perf_counter()
report = run_cases(cell, source, cases, DEFAULT_STEP_LIMIT)  # warm: every station's code compiled
run_s = time.perf_counter() - start
peak_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
print(json.dumps({{"cases": report.cases, "mismatches": report.mismatches + first.mismatches,
                  "cases_per_s": report.cases / run_s, "first_per_s": first.cases / first_s,
                  "load_s": load_s, "peak_mb": peak_mb}}))
"""


def measure(stations: int, target: str, cases: int) -> dict:
    with tempfile.TemporaryDirectory() as folder:
        code = CHILD.format(
            bench=str(Path(__file__).parent), stations=stations, target=target, cases=cases, folder=folder
        )
        proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return json.loads(proc.stdout.strip().splitlines()[-1])


def main() -> int:
    parser = argparse.ArgumentParser()
    parser.add_argument("--sizes", default="8,100,1000")
    parser.add_argument("--cases", type=int, default=2000)
    parser.add_argument("--targets", default="ur,kuka,abb,dtrans")
    args = parser.parse_args()
    sizes = [int(v) for v in args.sizes.split(",")]
    FIGURES.line(f"{args.cases} verified readings per size and target, one core, a fresh process each")
    FIGURES.line(f"{'stations':>8} {'target':<7} {'warm/s':>8} {'vs 8':>6} {'first/s':>8} {'load s':>7} {'peak MB':>8}")
    first: dict[str, float] = {}
    ok = True
    for stations in sizes:
        for target in args.targets.split(","):
            result = measure(stations, target, args.cases)
            ok = ok and result["mismatches"] == 0
            first.setdefault(target, result["cases_per_s"])
            ratio = result["cases_per_s"] / first[target]
            FIGURES.line(
                f"{stations:>8} {target:<7} {result['cases_per_s']:>8.0f} {ratio:>6.2f} "
                f"{result['first_per_s']:>8.0f} {result['load_s']:>7.2f} {result['peak_mb']:>8.0f}"
            )
    return 0 if ok else 1


if __name__ == "__main__":
    code = main()
    FIGURES.write()  # the figures into docs/benchmarks.md, dated, with the machine
    sys.exit(code)
