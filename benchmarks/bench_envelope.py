"""The envelope check at generate time (issue 10): the demo cell (goal <= 0.5 s) and a 1,000-station cell
(goal <= 5 s), and batched inverse kinematics in us per pose (goal <= 20 us).

Run: python benchmarks/bench_envelope.py [--stations N]. The large cell's stations are drawn at random in
front of the demo's arms; the ones the check refuses are dropped before the timed run (it reports how many).
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

HEAD = """[cell]
name = "bench_envelope"
targets = ["ur", "kuka", "abb", "dtrans"]
[cell.camera]
angle_sign = -1
[cell.robot]
ur = "UR10e"
kuka = "KR 10 R1100 sixx"
abb = "IRB 1600-10/1.45"
[cell.tool]
tcp = [0.0, 0.0, 200.0, 0.0, 0.0, 0.0]
mass_kg = 1.5
cog_mm = [0.0, 0.0, 80.0]
[cell.limits]
max_shift_mm = 10.0
max_rotation_deg = 10.0
"""


def draw(rng: random.Random) -> tuple[float, ...]:
    return rng.uniform(450, 750), rng.uniform(-350, 350), rng.uniform(-60, 60), rng.uniform(-90, 90)


def station(i: int, params: tuple[float, ...]) -> str:
    x, y, yaw, theta = params
    return (
        f'[[station]]\nid = {i}\nname = "machine_{i}"\nmark = [{x:.3f}, {y - 150:.3f}, {theta:.3f}]\n'
        "[station.poses]\n"
        f"approach = [{x:.3f}, {y:.3f}, 420.0, {yaw:.3f}, 0.0, 180.0]\n"
        f"work = [{x + 60:.3f}, {y + 10:.3f}, 320.0, {yaw:.3f}, 10.0, 180.0]\n"
    )


def passing_cell(count: int, folder: Path):
    """count stations that the envelope check accepts (random candidates, refused ones dropped)."""
    from codegen.kinds.station.plan import reach_proofs
    from codegen.kinds.station.section import stations_of
    from codegen.model.cell import load_cell

    rng = random.Random(7)
    kept: list[tuple[float, ...]] = []
    dropped = 0
    path = folder / "one.toml"
    while len(kept) < count:
        params = draw(rng)
        path.write_text(HEAD + station(1, params), encoding="utf-8")
        cell = load_cell(path)
        if any(refusal for t in ("ur", "kuka", "abb") for _, _, refusal in reach_proofs(cell, t, stations_of(cell))):
            dropped += 1
            continue
        kept.append(params)
    path = folder / "bench_envelope.toml"
    path.write_text(HEAD + "\n".join(station(i + 1, params) for i, params in enumerate(kept)), encoding="utf-8")
    return path, dropped


def timed_check(path) -> float:
    from codegen.kinds.station.plan import reach_proofs
    from codegen.kinds.station.section import stations_of
    from codegen.model.cell import load_cell

    cell = load_cell(path)  # a fresh cell: nothing worked out yet
    start = time.perf_counter()
    for target in ("ur", "kuka", "abb"):
        refused = [refusal for _, _, refusal in reach_proofs(cell, target, stations_of(cell)) if refusal]
        assert not refused, refused[0]
    return time.perf_counter() - start


def ik_us_per_pose(model: str, count: int = 100_000) -> float:
    import numpy as np

    from codegen.robot.arms import catalogue

    arm = catalogue()[model]
    rng = np.random.default_rng(1)
    poses = arm.kin.fk(rng.uniform(arm.limits[:, 0], arm.limits[:, 1], (count, 6)))
    arm.kin.ik(poses[:10])
    start = time.perf_counter()
    arm.kin.ik(poses)
    return (time.perf_counter() - start) / count * 1e6


def main() -> int:
    parser = argparse.ArgumentParser()
    parser.add_argument("--stations", type=int, default=1000)
    args = parser.parse_args()
    from codegen.model.cell import DEMO_CELL

    ok = True
    demo = min(timed_check(DEMO_CELL) for _ in range(3))
    FIGURES.line(f"envelope, demo cell (7 stations, 3 arms): {demo:6.3f} s (goal <= 0.5 s)")
    ok &= demo <= 0.5
    with tempfile.TemporaryDirectory() as tmp:
        path, dropped = passing_cell(args.stations, Path(tmp))
        big = timed_check(path)
    refused = f"{dropped} random candidates refused"
    FIGURES.line(f"envelope, {args.stations} stations (3 arms, {refused}): {big:6.2f} s (goal <= 5 s)")
    ok &= big <= 5.0
    for model in ("KR 10 R1100 sixx", "IRB 1600-10/1.45", "UR10e"):
        us = ik_us_per_pose(model)
        FIGURES.line(
            f"inverse kinematics, all 8 solutions, {model}: {us:5.2f} us per pose (batch of 100,000; goal <= 20)"
        )
        ok &= us <= 20.0
    return 0 if ok else 1


if __name__ == "__main__":
    code = main()
    FIGURES.write()  # the figures into docs/benchmarks.md, dated, with the machine
    sys.exit(code)
