"""A memo keyed by its arguments' exact values: functools.lru_cache takes 0.0 and -0.0 as one key."""

from __future__ import annotations

import math
from collections.abc import Callable
from functools import lru_cache, wraps


def _signs(values) -> tuple:
    """Each float's sign (a nested tuple's too): with the values, a key that tells -0.0 from 0.0."""
    return tuple(_signs(v) if isinstance(v, tuple) else math.copysign(1.0, v) if isinstance(v, float) else None
                 for v in values)


def exact_cache(maxsize: int) -> Callable:
    """lru_cache(maxsize) whose key also holds each float argument's sign, so a result worked out for -0.0 is never
    handed to a call with 0.0 (their results differ in the sign of a zero, and what follows can differ more: atan2)."""

    def decorate(fn: Callable) -> Callable:
        @lru_cache(maxsize=maxsize)
        def kept(signs: tuple, *args):
            return fn(*args)

        @wraps(fn)
        def call(*args):
            return kept(_signs(args), *args)

        call.cache_info, call.cache_clear = kept.cache_info, kept.cache_clear
        return call

    return decorate
