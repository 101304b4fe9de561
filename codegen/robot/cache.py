"""A value computed once per cell object: cells are frozen but hold dicts, so they are not hashable."""

from __future__ import annotations


def per_cell(store: dict, cell, key: tuple, compute):
    """compute() once per cell object and key (cells are frozen but hold dicts: not hashable). The
    entry keeps its cell, so an id reused by a later cell is not mistaken for it."""
    hit = store.get((id(cell), *key))
    if hit is None or hit[0] is not cell:
        hit = store[(id(cell), *key)] = (cell, compute())
    return hit[1]
