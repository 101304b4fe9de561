"""Render, check and generate a 1,000-station cell for all four targets (goals: render <= 2 s, issue 3;
the grammar check <= 2 s and generate <= 3 s, issue 16).

Run: python benchmarks/bench_render.py [--stations N]. Prints the render time, the grammar check of
every program (codegen/dialects/core/recognize.py) and generate (render + check + atomic write).
"""

from __future__ import annotations

import argparse
import random
import sys
import tempfile
import time
from pathlib import Path

from record import Figures

FIGURES = Figures(__file__)


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
    from codegen.generate import check_rendered, generate
    from codegen.model.cell import load_cell
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
        check_rendered(files)  # the first check builds each grammar's tables: counted, as in a CLI run
        check_s = time.perf_counter() - start
        start = time.perf_counter()
        generate(cell, None, Path(tmp) / "out")
        generate_s = time.perf_counter() - start
    FIGURES.line(f"{args.stations} stations, 4 targets, {len(files)} files, {size / 1e6:.1f} MB")
    goals = {"render": (render_s, 2.0), "check": (check_s, 2.0), "generate": (generate_s, 3.0)}
    for name, (seconds, goal) in goals.items():
        FIGURES.line(f"{name:8} {seconds:6.2f} s (goal <= {goal:.2f} s): {'ok' if seconds <= goal else 'OVER GOAL'}")
    FIGURES.line("check: the grammar check of every program; generate: render + check + atomic write")
    return 0 if all(seconds <= goal for seconds, goal in goals.values()) else 1


if __name__ == "__main__":
    code = main()
    FIGURES.write()  # the figures into docs/benchmarks.md, dated, with the machine
    sys.exit(code)
