"""Checks of a stack: boxes that overlap or overhang (refused), boxes poorly supported by the layer below (warned)."""

from __future__ import annotations

import math

import numpy as np

from codegen.kinds.pallet.patterns import Box

AREA_TOL = 1e-6  # share of a box's area: boxes that only touch do not overlap
CHUNK = 256  # rows of the bounding-box comparison at a time (256 x 2,000 boxes x 2: 1 MB)


def corners(box: Box, length: float, width: float) -> np.ndarray:
    """The box's footprint, 4 x 2, counterclockwise."""
    a = math.radians(box.ccw_deg)
    c, s = math.cos(a), math.sin(a)
    half = np.array([[-length, -width], [length, -width], [length, width], [-length, width]]) / 2
    return half @ np.array([[c, s], [-s, c]]) + np.array([box.x, box.y])


def _clip(subject: np.ndarray, clipper: np.ndarray) -> np.ndarray:
    """Sutherland-Hodgman: the part of a convex polygon inside another (both counterclockwise)."""
    out = subject
    for i in range(len(clipper)):
        if len(out) == 0:
            break
        a, b = clipper[i], clipper[(i + 1) % len(clipper)]
        edge = b - a
        side = edge[0] * (out[:, 1] - a[1]) - edge[1] * (out[:, 0] - a[0])  # >= 0: inside
        kept = []
        for j in range(len(out)):
            p, q, sp, sq = out[j], out[(j + 1) % len(out)], side[j], side[(j + 1) % len(out)]
            if sp >= 0:
                kept.append(p)
            if (sp >= 0) != (sq >= 0):
                kept.append(p + (q - p) * (sp / (sp - sq)))
        out = np.array(kept) if kept else np.zeros((0, 2))
    return out


def _area(polygon: np.ndarray) -> float:
    if len(polygon) < 3:
        return 0.0
    x, y = polygon[:, 0], polygon[:, 1]
    return 0.5 * abs(float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))))


def _candidates(a: list[np.ndarray], b: list[np.ndarray]) -> list[tuple[int, int]]:
    """Pairs whose bounding boxes overlap (a vectorised first pass; the clip runs on these only), in order
    of i, then j. Compared CHUNK rows of a at a time: the comparison's memory stays CHUNK x len(b) x 2."""
    if not a or not b:
        return []
    lo_a, hi_a = np.array([c.min(0) for c in a]), np.array([c.max(0) for c in a])
    lo_b, hi_b = np.array([c.min(0) for c in b]), np.array([c.max(0) for c in b])
    out = []
    for start in range(0, len(a), CHUNK):
        lo, hi = lo_a[start : start + CHUNK], hi_a[start : start + CHUNK]
        hit = np.all((lo[:, None] < hi_b[None]) & (lo_b[None] < hi[:, None]), axis=2)
        out.extend((int(i) + start, int(j)) for i, j in zip(*np.nonzero(hit), strict=True))
    return out


def overlaps(boxes: tuple[Box, ...], size: tuple[float, float]) -> list[tuple[int, int, float]]:
    """(i, j, area mm^2) for boxes i < j (0-based) that overlap."""
    shapes = [corners(b, *size) for b in boxes]
    limit = AREA_TOL * size[0] * size[1]
    found = []
    for i, j in _candidates(shapes, shapes):
        if i < j:
            area = _area(_clip(shapes[i], shapes[j]))
            if area > limit:
                found.append((i, j, area))
    return found


def overhangs(
    boxes: tuple[Box, ...], size: tuple[float, float], pallet: tuple[float, float]
) -> list[tuple[int, float]]:
    """(i, mm) for each box reaching beyond the pallet's edge, by how far."""
    out = []
    for i, box in enumerate(boxes):
        c = corners(box, *size)
        beyond = max(-c[:, 0].min(), c[:, 0].max() - pallet[0], -c[:, 1].min(), c[:, 1].max() - pallet[1])
        if beyond > 1e-6:
            out.append((i, float(beyond)))
    return out


def support(upper: tuple[Box, ...], lower: tuple[Box, ...], size: tuple[float, float]) -> list[float]:
    """The share of each upper box's bottom that rests on the boxes below."""
    top, below = [corners(b, *size) for b in upper], [corners(b, *size) for b in lower]
    rested = [0.0] * len(top)
    for i, j in _candidates(top, below):
        rested[i] += _area(_clip(top[i], below[j]))
    return [min(1.0, r / (size[0] * size[1])) for r in rested]
