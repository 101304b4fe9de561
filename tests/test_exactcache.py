"""A memo keyed by exact values: a result worked out for -0.0 is never handed to a call with 0.0."""

from __future__ import annotations

import math

from codegen.dialects.posemath import rotmat_from_zyx_deg
from codegen.exactcache import exact_cache


def _bits(values) -> list[str]:
    return [float(v).hex() for v in values]


def test_minus_zero_and_zero_are_two_keys():
    """functools.lru_cache gave rotmat_from_zyx_deg(-0.0, 0.0, 0.0) the matrix of (0.0, 0.0, 0.0) when that came first
    (or the other way round): a run's trace then depended on what the process had run before (the recorded traces of
    the examples differed in 198 runs after other tests in the same worker)."""
    first = rotmat_from_zyx_deg(0.0, 0.0, 0.0)
    second = rotmat_from_zyx_deg(-0.0, 0.0, 0.0)
    fresh = rotmat_from_zyx_deg.__wrapped__(-0.0, 0.0, 0.0)
    assert _bits(second) == _bits(fresh) and _bits(first) != _bits(second)


def test_nested_values_and_other_types_keep_their_keys():
    calls = []

    @exact_cache(maxsize=8)
    def f(values: tuple, n: int):
        calls.append((values, n))
        return math.copysign(1.0, values[0]) * n

    assert f((0.0, 1.0), 2) == 2.0 and f((-0.0, 1.0), 2) == -2.0 and f((0.0, 1.0), 2) == 2.0
    assert len(calls) == 2 and f.cache_info().hits == 1
