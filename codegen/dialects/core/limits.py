"""The interpreter's bounds on what a program declares, where the controllers' manuals give none it could cite."""

from __future__ import annotations

import math

# elements of one array: the controllers' manuals consulted give no number (unconfirmed); a million
# elements is far beyond any generated program's arrays (tens of elements) and within what a run holds in memory
ARRAY_ELEMENTS_MAX = 1_000_000


def array_size_problem(sizes: list) -> str | None:
    """Why an array of these dimensions cannot be declared (None: it can): each a whole number of at least 1, and
    all its elements together within the bound."""
    for size in sizes:
        if isinstance(size, bool) or not float(size).is_integer() or size < 1:
            return f"an array's dimension must be a whole number of at least 1, got {size:g}"
    total = math.prod(int(size) for size in sizes)
    if total > ARRAY_ELEMENTS_MAX:
        return (
            f"an array of {total:,} elements; the interpreter holds at most {ARRAY_ELEMENTS_MAX:,} in one array (the "
            "controllers' own limit could not be confirmed)"
        )
    return None
