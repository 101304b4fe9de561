"""Pattern generation and every check of a 1,000-box layout (overlap, overhang, support on a mirrored layer).

Goal (palletizing issue): <= 0.2 s. Run: python benchmarks/bench_pallet.py [--runs N]
"""

from __future__ import annotations

import argparse
import statistics
import time

from codegen.pallet import checks
from codegen.pallet.patterns import Box, split_row

SIZE = (50.0, 40.0)  # box footprint, mm
PALLET = (1300.0, 1600.0)  # 40 rows of split-row, 26 and 25 boxes: 1,020 boxes


def once() -> tuple[float, int]:
    start = time.perf_counter()
    boxes = tuple(split_row(*PALLET, *SIZE))
    mirrored = tuple(Box(PALLET[0] - b.x, b.y, -b.ccw_deg) for b in boxes)
    assert not checks.overlaps(boxes, SIZE) and not checks.overhangs(boxes, SIZE, PALLET)
    checks.support(mirrored, boxes, SIZE)
    return time.perf_counter() - start, len(boxes)


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--runs", type=int, default=5)
    runs = parser.parse_args().runs
    times, count = zip(*(once() for _ in range(runs)), strict=True)
    median, low, high = statistics.median(times), min(times), max(times)
    print(f"{count[0]} boxes: median {median:.3f} s, range {low:.3f}-{high:.3f} s (goal <= 0.2 s)")


if __name__ == "__main__":
    main()
