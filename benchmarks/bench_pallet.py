"""Pattern generation and every check of a 1,000-box layout (overlap, overhang, support on a mirrored layer),
and one full stacking cycle of the EUR pallet verified per target (run, reference and comparison).

Goals (palletizing issue): <= 0.2 s; <= 1 s per pallet. Run: python benchmarks/bench_pallet.py [--runs N]
"""

from __future__ import annotations

import argparse
import statistics
import time

from record import Figures

from codegen.kinds.pallet import checks
from codegen.kinds.pallet.patterns import Box, split_row

FIGURES = Figures(__file__)

SIZE = (50.0, 40.0)  # box footprint, mm
PALLET = (1300.0, 1600.0)  # 40 rows of split-row, 26 and 25 boxes: 1,020 boxes


def once() -> tuple[float, int]:
    start = time.perf_counter()
    boxes = tuple(split_row(*PALLET, *SIZE))
    mirrored = tuple(Box(PALLET[0] - b.x, b.y, -b.ccw_deg) for b in boxes)
    assert not checks.overlaps(boxes, SIZE) and not checks.overhangs(boxes, SIZE, PALLET)
    checks.support(mirrored, boxes, SIZE)
    return time.perf_counter() - start, len(boxes)


def full_stack(runs: int) -> None:
    """Seconds for the full_stack case of the EUR pallet (5 layers, 30 boxes, 2 slip sheets, with the arm) per target:
    the program run and judged as `codegen verify` does (codegen.verify.runner), the program loaded once."""
    from pathlib import Path

    from codegen.dialects.core.machine import DEFAULT_STEP_LIMIT
    from codegen.kinds.pallet.cases import PalletRun
    from codegen.kinds.pallet.cycle import PalletCase
    from codegen.model.cell import load_cell
    from codegen.verify.plan import Case
    from codegen.verify.programs import fresh_sources
    from codegen.verify.runner import run_cases

    cell = load_cell(Path(__file__).resolve().parents[1] / "codegen" / "examples" / "pallets" / "eur_pallet.toml")
    case = Case("full_stack", PalletRun(0, PalletCase("full_stack", 1, 1)))
    for target in cell.targets:
        source = fresh_sources(cell, [target], only={"pallet"})[0]
        source.load()  # parsed once, as verify's workers do
        times = []
        for _ in range(runs):
            start = time.perf_counter()
            row = run_cases(cell, source, [case], DEFAULT_STEP_LIMIT)
            times.append(time.perf_counter() - start)
        assert row.mismatches == 0, row.first_mismatches
        low, high = min(times), max(times)
        boxes = row.figures.boxes if row.figures is not None else 0
        FIGURES.line(f"  {target}: full EUR stack ({boxes} boxes) verified in {low:.3f}-{high:.3f} s (goal <= 1 s)")


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--runs", type=int, default=5)
    runs = parser.parse_args().runs
    times, count = zip(*(once() for _ in range(runs)), strict=True)
    median, low, high = statistics.median(times), min(times), max(times)
    FIGURES.line(f"{count[0]} boxes: median {median:.3f} s, range {low:.3f}-{high:.3f} s (goal <= 0.2 s)")
    full_stack(runs)


if __name__ == "__main__":
    main()
    FIGURES.write()  # the figures into docs/benchmarks.md, dated, with the machine
