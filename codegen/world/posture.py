"""Choosing the arm's posture to clear the cell, for any kind: the candidates, the tie margin and the ranking."""

# Where the cell names no configuration, the controller leaves the choice to the program. The candidates: first the
# posture the controller takes from the home by itself (each joint pose's solution nearest the home), then each
# analytic branch that takes every joint pose within the joint limits (its solution nearest the home), nearer the home
# first. A kind proves each (reach, clearance) and ranks them by their least clearance: a candidate further on
# replaces the one kept so far only where it clears by more than TIE_MM more.

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from codegen.robot import solve
from codegen.world.bodies import arm_bodies

# Two postures whose least clearances differ by less than this are equally clear: the arm's capsules are estimates
# rounded up by more (docs/clearance.md, Sources), and swinging the arm into another configuration for less is not
# worth its longer way from the home.
TIE_MM = 1.0


@dataclass(frozen=True)
class Posture:
    """A candidate posture: the kind's configuration (what its program names), the analytic branch (-1: the
    controller's own nearest-home solutions, which may mix branches), how far its first joint pose lies from the home
    (deg, Euclidean) and its least clearance (mm; None: it does not reach or does not clear)."""

    config: object
    branch: int
    travel_deg: float
    least_mm: float | None = None
    refusal: str = ""
    reaches: bool = True  # False: refused by the reach proof
    nearest: object = None  # the proof's Least: where the least clearance is
    proven: object = None  # the kind's proofs of the posture where it passed them (handed on in the kind's plan)


def branch_joints(arm, solutions: np.ndarray, home) -> tuple[np.ndarray, list[tuple[int, np.ndarray]]]:
    """For the joint poses' analytic solutions (n, 8, 6): the controller's own choice from the home (each pose's
    solution nearest the home: (n, 6), NaN rows where none is within the limits), and each other branch that takes
    every pose within the limits with its joints (each nearest the home within the branch), nearer the home first
    (by the first pose's distance, then the branch)."""
    home = np.broadcast_to(np.asarray(home, dtype=float), (len(solutions), 6))
    natural, _ = solve.nearest(arm, solutions, home)
    others = []
    for b in range(solutions.shape[1]):
        q, _ = solve.nearest(arm, solutions[:, b : b + 1], home)
        if not np.isnan(q).any() and not np.array_equal(q, natural):
            others.append((b, q))
    return natural, sorted(others, key=lambda item: (float(np.linalg.norm(item[1][0] - home[0])), item[0]))


def branch_count(arm) -> int:
    """How many analytic branches the arm's inverse kinematics gives (its configurations)."""
    return solve.branches(arm, arm.kin.fk(np.zeros(6))[None]).shape[-2]


def in_order(postures: list[Posture]) -> list[Posture]:
    """Candidates in the order they are tried: nearer the home first, then by branch."""
    return sorted(postures, key=lambda p: (p.travel_deg, p.branch))


def travel(joints, home) -> float:
    """How far (deg, Euclidean) joints lie from the home."""
    return float(np.linalg.norm(np.asarray(joints, dtype=float) - np.asarray(home, dtype=float)))


def choose(first: Posture, others: list[Posture], evaluate: Callable[[Posture, float | None], Posture]):
    """Of the postures in order (the controller's own first, proven already), the one kept: one further on replaces the
    one kept so far only where evaluate(posture, bar) finds it clear by at least bar (the kept one's least clearance
    plus TIE_MM; None: the cell's clearance, nothing kept yet); None where none clears."""
    best = first if first.least_mm is not None else None
    for posture in others:
        bar = None if best is None else best.least_mm + TIE_MM
        tried = evaluate(posture, bar)
        if tried.least_mm is not None:
            best = tried
    return best


def set_by_the_tool(arm, least) -> bool:
    """The least clearance (a proof's Least) is the tool's or the part's from a solid at a pose the program stands at (a
    move's start or end): the TCP is there in every posture, so no other posture can keep more (no search needed)."""
    found = least.found
    own = {body.name for body in arm_bodies(arm)} | {"tool", "part"}
    return found.body in ("tool", "part") and found.other not in own and found.s in (0.0, 1.0)
