"""Closed-form kinematics speed: ik and fk per call and per pose, small and large batches.

Goals: ik on 1 and on 4 poses <= 60 us per call (OPW) and <= 80 us (UR); fk on 1 pose <= 25 us; large
batches (10,000 poses) about 2-3 us per pose for ik. The verifier calls ik/fk once or twice per verified case
with one to four poses, so the small batches set its speed. ik on up to SMALL_BATCH poses runs pose by pose on
Python floats, larger batches in numpy (codegen/robot/kinematics.py).

Measured on one OPW arm (catalogue "KR 10 R1100 sixx") and one UR arm ("UR10e"), random axis values within
the arm's limits; each figure is the median over --repeat timed rounds after a warm-up, each round as many
calls as make about --round-ms milliseconds (the machine is shared: expect spread).

Run: python benchmarks/bench_kinematics.py [--repeat N] [--round-ms MS]
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time

import numpy as np
from record import Figures

FIGURES = Figures(__file__)

ARMS = ("KR 10 R1100 sixx", "UR10e")
BATCHES = (1, 4, 100, 10_000)
GOALS_US = {("ik", 1): {"opw": 60.0, "ur": 80.0}, ("ik", 4): {"opw": 60.0, "ur": 80.0}, ("fk", 1): 25.0}


def per_call_us(call, argument, repeat: int, round_ms: float) -> float:
    """Median time of one call (us) over `repeat` rounds, after a warm-up that also sizes the rounds."""
    start = time.perf_counter()
    calls = 0
    while time.perf_counter() - start < 0.02 or calls < 3:
        call(argument)
        calls += 1
    per_call = (time.perf_counter() - start) / calls
    count = max(1, int(round_ms * 1e-3 / per_call))
    rounds = []
    for _ in range(repeat):
        start = time.perf_counter()
        for _ in range(count):
            call(argument)
        rounds.append((time.perf_counter() - start) / count)
    return statistics.median(rounds) * 1e6


def goal_for(function: str, batch: int, family: str) -> float | None:
    goal = GOALS_US.get((function, batch))
    return goal.get(family) if isinstance(goal, dict) else goal


def main() -> int:
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeat", type=int, default=15)
    parser.add_argument("--round-ms", type=float, default=20.0)
    args = parser.parse_args()
    from codegen.robot.arms import catalogue

    rng = np.random.default_rng(0)
    missed = 0
    FIGURES.line(f"{'arm':<18} {'call':<4} {'poses':>6} {'us/call':>10} {'us/pose':>9}  goal")
    for name in ARMS:
        arm = catalogue()[name]
        limits = np.clip(arm.limits, -179.0, 179.0)
        for batch in BATCHES:
            joints = rng.uniform(limits[:, 0], limits[:, 1], (batch, 6))
            if batch == 1:
                joints = joints[0]  # one pose as (6,) and (4, 4), the way the interpreter calls
            poses = arm.kin.fk(joints)
            for function, call, argument in (("ik", arm.kin.ik, poses), ("fk", arm.kin.fk, joints)):
                repeat = args.repeat if batch < 10_000 else max(3, args.repeat // 3)
                us = per_call_us(call, argument, repeat, args.round_ms)
                goal = goal_for(function, batch, arm.family)
                verdict = "" if goal is None else f"<= {goal:g} us/call: " + ("ok" if us <= goal else "OVER GOAL")
                missed += goal is not None and us > goal
                FIGURES.line(f"{name:<18} {function:<4} {batch:>6} {us:>10.1f} {us / batch:>9.2f}  {verdict}")
    return 1 if missed else 0


if __name__ == "__main__":
    code = main()
    FIGURES.write()  # the figures into docs/benchmarks.md, dated, with the machine
    sys.exit(code)
