"""Interpreter speed: verified cases per second per dialect, and the demo cell's full verify.

Goals (issue 4): >= 5,000 verified cases/s per dialect; demo full verify (7 stations x 4 targets x
1,000 random readings plus edge cases) <= 15 s wall. Run: python benchmarks/bench_verify.py
"""

from __future__ import annotations

import subprocess
import sys
import time


def main() -> int:
    from codegen.cell import load_cell
    from codegen.verify import build_cases, fresh_programs, verify

    cell = load_cell()
    cases = build_cases(cell, 300, 7)
    print(f"per dialect, {len(cases)} readings of the demo cell (parse once, run many):")
    for target in cell.targets:
        start = time.perf_counter()
        programs = fresh_programs(cell, [target])
        parse_s = time.perf_counter() - start
        report = verify(cell, [target], programs, cases)[0]
        print(
            f"  {target:<7} {report.cases / report.seconds:7.0f} verified cases/s "
            f"(render + parse {parse_s * 1000:.0f} ms; mismatches {report.mismatches})"
        )
    start = time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "codegen", "verify"], capture_output=True, text=True)
    wall = time.perf_counter() - start
    print(proc.stdout.strip())
    print(f"full `codegen verify` on the demo cell: {wall:.1f} s wall (goal <= 15 s)")
    return proc.returncode


if __name__ == "__main__":
    sys.exit(main())
