"""Clearance checking speed: exact distance queries per second, one configuration of a whole arm against a cell's
solids, and one joint move and one linear move checked along their paths.

The cell: a UR5e with a 150 mm tool of radius 30 and a 100 x 80 x 60 mm carried box, the floor, a machine (a box
800 x 600 x 180 mm in front of the robot) and a fence (a box behind it); the moves start at the catalogue's home.
Each figure is the median over --repeat rounds (the machine is shared: expect spread). No goal is set: these
figures are the baseline the cell-level check (every move of a verify) is measured against.

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
from codegen.world.sweep import CLEARANCE_MM, check_path, joint_path, linear_path

FIGURES = Figures(__file__)


def median_time(function, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


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
                 f"the others ruled out by bounding spheres)")

    target = home.copy()
    target[0] += 120.0
    target[1] += 30.0
    joint = median_time(lambda: check_path(scene, joint_path(home, target), home, CLEARANCE_MM), args.repeat)
    result = check_path(scene, joint_path(home, target), home, CLEARANCE_MM)
    FIGURES.line(f"joint move (axis 1 +120, axis 2 +30 deg), clearance {CLEARANCE_MM:g} mm: {joint * 1e3:7.1f} ms, "
                 f"{result.samples} samples, least {result.distance:.1f} mm ({result.body} - {result.other})")

    start = arm.kin.fk(home) @ tool
    end = start.copy()
    end[:3, 3] += (0.0, 300.0, -200.0)
    path = linear_path(arm, tool, start, end)
    linear = median_time(lambda: check_path(scene, path, home, CLEARANCE_MM), args.repeat)
    result = check_path(scene, path, home, CLEARANCE_MM)
    FIGURES.line(f"linear move (300 mm sideways, 200 mm down), clearance {CLEARANCE_MM:g} mm: {linear * 1e3:7.1f} ms, "
                 f"{result.samples} samples, least {result.distance:.1f} mm ({result.body} - {result.other})")
    FIGURES.write()  # the figures into docs/benchmarks.md, dated, with the machine
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
