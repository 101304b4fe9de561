"""Render a generated 1,000-station cell for all four targets (goal: <= 2 s wall, issue 3).

Run: python benchmarks/bench_render.py [--stations N]. Prints render time, and generate time
(render + parsing every program with its grammar + atomic write) for comparison.
"""

from __future__ import annotations

import argparse
import random
import sys
import tempfile
import time
from pathlib import Path


def make_cell(stations: int, seed: int = 1) -> str:
    rng = random.Random(seed)
    lines = [
        '[cell]\nname = "bench_cell"\ntargets = ["ur", "kuka", "abb", "dtrans"]\n',
        "[cell.camera]\nangle_sign = -1\n[cell.limits]\nmax_shift_mm = 10.0\nmax_rotation_deg = 10.0\n",
    ]
    for i in range(1, stations + 1):
        x, y = rng.uniform(300, 900), rng.uniform(-600, 600)
        theta = rng.uniform(-180, 180)
        lines.append(
            f'[[station]]\nid = {i}\nname = "machine_{i}"\nmark = [{x:.3f}, {y:.3f}, {theta:.3f}]\n'
            "[station.poses]\n"
            f"approach = [{x + 40:.3f}, {y + 120:.3f}, 420.0, {rng.uniform(-180, 180):.3f}, 0.0, 180.0]\n"
            f"work = [{x + 120:.3f}, {y + 130:.3f}, 300.0, {rng.uniform(-180, 180):.3f}, 10.0, 180.0]\n"
        )
    return "\n".join(lines)


def main() -> int:
    parser = argparse.ArgumentParser()
    parser.add_argument("--stations", type=int, default=1000)
    args = parser.parse_args()
    from codegen.cell import load_cell
    from codegen.generate import generate
    from codegen.render import render

    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "bench_cell.toml"
        path.write_text(make_cell(args.stations), encoding="utf-8")
        cell = load_cell(path)
        start = time.perf_counter()
        files = render(cell)
        render_s = time.perf_counter() - start
        size = sum(len(f.text) for f in files)
        start = time.perf_counter()
        generate(cell, None, Path(tmp) / "out")
        generate_s = time.perf_counter() - start
    print(f"{args.stations} stations, 4 targets, {len(files)} files, {size / 1e6:.1f} MB")
    print(f"render   {render_s:6.2f} s (goal <= 2.00 s): {'ok' if render_s <= 2.0 else 'OVER GOAL'}")
    print(f"generate {generate_s:6.2f} s (render + grammar check of every program + atomic write)")
    return 0 if render_s <= 2.0 else 1


if __name__ == "__main__":
    sys.exit(main())
