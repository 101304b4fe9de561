"""Clearance checking speed: exact distance queries per second, one configuration of a whole arm against a cell's
solids, and one joint move and one linear move checked along their paths.

The cell: a UR5e with a 150 mm tool of radius 30 and a 100 x 80 x 60 mm carried box, the floor, a machine (a box
800 x 600 x 180 mm in front of the robot) and a fence (a box behind it); the moves start at the catalogue's home.
Each figure is the median over --repeat rounds (the machine is shared: expect spread). Beside each move, the same move
sampled the way the sweep did before conservative advancement (every step half the clearance of travel, every sample
measured): the before and after of the same run. No goal is set.

Run: python benchmarks/bench_clearance.py [--repeat N]
"""

from __future__ import annotations

import argparse
import statistics
import time

import coal
import numpy as np
from record import Figures

from codegen.robot.arms import catalogue
from codegen.world.engine import Scene
from codegen.world.solids import Box, Floor, World, part_box, tool_cylinder, translation
from codegen.world.sweep import CLEARANCE_MM, check_path, joint_path, linear_path, travel_weights

FIGURES = Figures(__file__)


def median_time(function, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def fixed_step(scene: Scene, path, q_start, clearance_mm: float) -> tuple[float, int]:
    """The move's least sampled distance and sample count with a fixed step: samples added until no step's travel
    bound exceeds half the clearance, every sample then measured (the sweep before conservative advancement)."""
    weights, half = travel_weights(scene), 0.5 * clearance_mm
    s, q = [0.0, 1.0], [np.asarray(q_start, dtype=float)]
    q.append(path(1.0, q[0]))
    i = 0
    while i < len(s) - 1:
        travel = float(weights @ np.abs(q[i + 1] - q[i]))
        if travel > half:
            pieces = int(np.ceil(travel / half))
            middle = [s[i] + (s[i + 1] - s[i]) * k / pieces for k in range(1, pieces)]
            solved, near = [], q[i]
            for value in middle:
                near = path(value, near)
                solved.append(near)
            s[i + 1 : i + 1], q[i + 1 : i + 1] = middle, solved
            continue
        i += 1
    _, best = scene.least(np.array(q))
    return best.distance, len(s)


def main() -> int:
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeat", type=int, default=7)
    args = parser.parse_args()
    arm = catalogue()["UR5e"]
    tool = translation(0.0, 0.0, 150.0)
    world = World({
        "floor": Floor(0.0),
        "machine": Box((600.0, 800.0, 180.0), translation(650.0, 0.0, 90.0)),
        "fence": Box((40.0, 1600.0, 1800.0), translation(-1100.0, 0.0, 900.0)),
    })
    scene = Scene(arm, world, tool=tool_cylinder(tool, 30.0), part=part_box((100.0, 80.0, 60.0), tool))
    home = np.array(arm.home_deg)

    capsule, box = coal.Capsule(47.0, 425.0), coal.Box(600.0, 800.0, 180.0)
    near, where = coal.Transform3s(np.eye(3), np.array([0.0, 0.0, 300.0])), coal.Transform3s()
    request, result = coal.DistanceRequest(), coal.DistanceResult()
    count = 20_000
    per = median_time(lambda: [coal.distance(capsule, near, box, where, request, result) for _ in range(count)],
                      args.repeat) / count
    FIGURES.line(f"one capsule-box distance query (coal, shapes made once)  {per * 1e6:6.2f} us  {1 / per:9.0f} /s")

    rng = np.random.default_rng(1)
    configurations = home + rng.uniform(-40.0, 40.0, (200, 6))
    full = median_time(lambda: scene.nearest(configurations), args.repeat) / len(configurations)
    before = scene.queries
    scene.nearest(configurations)
    queries = (scene.queries - before) / len(configurations)
    FIGURES.line(f"one configuration, every pair ({len(scene.bodies)} bodies, {len(world.solids)} solids, "
                 f"{len(scene.pairs)} self pairs)  {full * 1e3:6.2f} ms   ({queries:.1f} exact queries each, "
                 f"the others ruled out by the cheap bounds)")

    target = home.copy()
    target[0] += 120.0
    target[1] += 30.0
    moves = [("joint move (axis 1 +120, axis 2 +30 deg)", joint_path(home, target), home)]

    start = arm.kin.fk(home) @ tool
    end = start.copy()
    end[:3, 3] += (0.0, 300.0, -200.0)
    moves.append(("linear move (300 mm sideways, 200 mm down)", linear_path(arm, tool, start, end), home))
    clear = home.copy()
    clear[0] -= 90.0  # facing the fence's side, the tool high: nothing within 100 mm
    clear[2] += 30.0
    moves.append(("joint move kept clear (axis 1 -90, axis 3 +30 deg)", joint_path(home, clear), home))
    for name, path, q0 in moves:
        after = median_time(lambda: check_path(scene, path, q0, CLEARANCE_MM), args.repeat)  # noqa: B023
        before = median_time(lambda: fixed_step(scene, path, q0, CLEARANCE_MM), args.repeat)  # noqa: B023
        result = check_path(scene, path, q0, CLEARANCE_MM)
        least, samples = fixed_step(scene, path, q0, CLEARANCE_MM)
        FIGURES.line(f"{name}, clearance {CLEARANCE_MM:g} mm: {after * 1e3:7.1f} ms, {result.samples} samples, least "
                     f"{result.distance:.1f} mm ({result.body} - {result.other}), at least {result.lower_bound:.1f}; "
                     f"fixed step: {before * 1e3:7.1f} ms, {samples} samples, least {least:.1f} mm")
    FIGURES.write()  # the figures into docs/benchmarks.md, dated, with the machine
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
