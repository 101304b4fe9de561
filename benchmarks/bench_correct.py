"""Wall time of `codegen correct` beside `python -c "import numpy"`, measured in the same run.

Goal (issue 2): correct <= 2x the numpy import. Run: python benchmarks/bench_correct.py [--runs N]
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import time

from record import Figures

FIGURES = Figures(__file__)


def wall(cmd: list[str], runs: int) -> float:
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def main() -> int:
    parser = argparse.ArgumentParser()
    parser.add_argument("--runs", type=int, default=15)
    args = parser.parse_args()
    numpy_s = wall([sys.executable, "-c", "import numpy"], args.runs)
    correct_s = wall(
        [sys.executable, "-m", "codegen", "correct", "--station", "1", "--mark", "614,-283,2.5"], args.runs
    )
    ratio = correct_s / numpy_s
    FIGURES.line(f"import numpy     median {numpy_s * 1000:7.1f} ms over {args.runs} runs")
    FIGURES.line(f"codegen correct  median {correct_s * 1000:7.1f} ms over {args.runs} runs")
    FIGURES.line(f"ratio {ratio:.2f} (goal <= 2.00): {'ok' if ratio <= 2.0 else 'OVER GOAL'}")
    return 0 if ratio <= 2.0 else 1


if __name__ == "__main__":
    code = main()
    FIGURES.write()  # the figures into docs/benchmarks.md, dated, with the machine
    sys.exit(code)
