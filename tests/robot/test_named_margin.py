"""The place verify names for a least margin does not depend on how the cases were split among workers."""

from __future__ import annotations

import itertools

import numpy as np

from codegen.robot.expect import JOINT_TOLERANCE_DEG, _Named


def _named(parts: list[list[float]]) -> str:
    out = None
    start = 0
    for part in parts:
        one = _Named()
        one.add(np.array(part), lambda i, start=start: f"place {start + i}")
        start += len(part)
        if out is None:
            out = one
        else:
            out.merge(one)
    return out.place


def test_a_split_names_the_place_one_run_names():
    """75.15, 75.12, 75.083 deg: the least is 75.083 and the first place within 0.05 deg of it is the second (75.12).
    The rule that kept a name until a margin came 0.05 deg below it named the first place (75.15: 0.067 deg above the
    least) when the cases came in two parts, and the third when they came in one: the demo's wrist margin was named
    at one move alone and at another with two workers."""
    margins = [75.15, 75.12, 75.083]
    assert margins[1] <= min(margins) + JOINT_TOLERANCE_DEG < margins[0]
    assert _named([margins]) == "place 1"
    for cut in range(1, len(margins)):
        assert _named([margins[:cut], margins[cut:]]) == "place 1", cut


def test_every_split_of_random_margins_names_the_first_within_the_tolerance():
    rng = np.random.default_rng(3)
    for _ in range(200):
        margins = list(np.round(rng.uniform(10.0, 10.2, 8), 3))
        least = min(margins)
        first = next(i for i, m in enumerate(margins) if m <= least + JOINT_TOLERANCE_DEG)
        for cuts in itertools.combinations(range(1, 8), 2):
            parts = [margins[: cuts[0]], margins[cuts[0] : cuts[1]], margins[cuts[1] :]]
            assert _named(parts) == f"place {first}", (margins, cuts)
