"""Layer patterns: explicit layouts and the generated families (column, interlock, pinwheel, split-row)."""

from __future__ import annotations

import math
from dataclasses import dataclass

from codegen.kinds.pallet.section import BOXES_MAX, FamilySpec, Pallet

FIT_CAP = 10**9  # a count of boxes along one side beyond this is only ever refused (and keeps int() finite)


class TooManyBoxes(ValueError):
    """A family that would put more than the limit of boxes on the layer (counted before any is made)."""

    def __init__(self, count: int) -> None:
        super().__init__(f"{count} boxes")
        self.count = count


@dataclass(frozen=True)
class Box:
    """A box of a layer: its centre on the pallet (mm, pallet frame) and its turn counterclockwise
    seen from above (deg); at 0 its length lies along the pallet's x."""

    x: float
    y: float
    ccw_deg: float


def layout(pallet: Pallet, name: str) -> tuple[Box, ...]:
    """The boxes of a pattern in placing order."""
    spec = pallet.patterns[name]
    if not isinstance(spec, FamilySpec):
        sign = -1.0 if pallet.angle_sense == "cw" else 1.0
        return tuple(Box(x, y, sign * angle) for x, y, angle in spec)
    length, width = pallet.size
    boxes = FAMILIES[spec.family](length, width, pallet.box[0], pallet.box[1])  # TooManyBoxes beyond BOXES_MAX
    if spec.label_out:
        boxes = [_label_out(b, length, width) for b in boxes]
    if spec.mirror:
        boxes = [Box(length - b.x, b.y, -b.ccw_deg) for b in boxes]
    return tuple(Box(round(b.x, 6), round(b.y, 6), _wrap(b.ccw_deg)) for b in boxes)


def cell_angle(pallet: Pallet, box: Box) -> float:
    """The box's angle as the cell writes it (its angle_sense)."""
    return _wrap(-box.ccw_deg if pallet.angle_sense == "cw" else box.ccw_deg)


def label_normal(box: Box) -> tuple[float, float]:
    """Which way the box's label faces on the pallet: its long side at -y when the box is at angle 0."""
    a = math.radians(box.ccw_deg)
    return (math.sin(a), -math.cos(a))


def _wrap(angle: float) -> float:
    wrapped = (angle + 180.0) % 360.0 - 180.0
    return 180.0 if wrapped == -180.0 else (0.0 if wrapped == 0 else wrapped)


def _label_out(box: Box, length: float, width: float) -> Box:
    """Turned half a turn where that makes the label face away from the pallet's centre."""
    nx, ny = label_normal(box)
    if nx * (box.x - length / 2) + ny * (box.y - width / 2) < -1e-9:
        return Box(box.x, box.y, box.ccw_deg + 180.0)
    return box


def _centred(boxes: list[Box], extent_x: float, extent_y: float, length: float, width: float) -> list[Box]:
    dx, dy = (length - extent_x) / 2, (width - extent_y) / 2
    return [Box(b.x + dx, b.y + dy, b.ccw_deg) for b in boxes]


def _grid(nx: int, ny: int, step_x: float, step_y: float, angle: float, x0: float = 0.0, y0: float = 0.0) -> list[Box]:
    return [Box(x0 + (i + 0.5) * step_x, y0 + (j + 0.5) * step_y, angle) for j in range(ny) for i in range(nx)]


def _fit(length: float, size: float) -> int:
    """How many of `size` fit in `length` (negative when even half of one does not: split_row's shift)."""
    return int(min(length // size, FIT_CAP))


def _limited(count: int, limit: int) -> None:
    """A layout is made only once its count is known to be within the limit (a box of 1 mm on a EUR pallet
    would make 960,000 of them)."""
    if count > limit:
        raise TooManyBoxes(count)


def column(length: float, width: float, bl: float, bw: float, limit: int = BOXES_MAX) -> list[Box]:
    """Every box the same way (the way that holds more), in rows, centred: boxes stand on boxes."""
    along = (_fit(length, bl), _fit(width, bw))
    across = (_fit(length, bw), _fit(width, bl))
    if along[0] * along[1] >= across[0] * across[1]:
        nx, ny = along
        _limited(nx * ny, limit)
        return _centred(_grid(nx, ny, bl, bw, 0.0), nx * bl, ny * bw, length, width)
    nx, ny = across
    _limited(nx * ny, limit)
    return _centred(_grid(nx, ny, bw, bl, 90.0), nx * bw, ny * bl, length, width)


def interlock(length: float, width: float, bl: float, bw: float, limit: int = BOXES_MAX) -> list[Box]:
    """A block of boxes along x from the pallet's x = 0 edge, then a block turned 90 deg: the split that
    holds the most boxes with both blocks present (its mirror on the next layer crosses the seams);
    a column layout where no such split fits."""
    rows_along, rows_across = _fit(width, bw), _fit(width, bl)
    best: tuple[int, int, int] | None = None  # count, i, k
    if rows_along >= 1 and rows_across >= 1:
        # a block of i boxes along holds at least i: past limit + 1 a split either exceeds the limit or has
        # no room left for the turned block (k falls as i grows), so the search ends there
        for i in range(1, min(_fit(length, bl), limit + 1) + 1):
            k = _fit(length - i * bl, bw)
            if k < 1:
                continue
            count = i * rows_along + k * rows_across
            if best is None or count > best[0]:
                best = (count, i, k)
    if best is None:
        return column(length, width, bl, bw, limit)
    count, i, k = best
    _limited(count, limit)
    left = _grid(i, rows_along, bl, bw, 0.0, 0.0, (width - rows_along * bw) / 2)
    right = _grid(k, rows_across, bw, bl, 90.0, i * bl, (width - rows_across * bl) / 2)
    return left + right


def pinwheel(length: float, width: float, bl: float, bw: float, limit: int = BOXES_MAX) -> list[Box]:
    """Units of four boxes turning about a centre (square side length + width), tiled and centred."""
    side = bl + bw
    nx, ny = _fit(length, side), _fit(width, side)
    _limited(4 * nx * ny, limit)
    unit = [
        (bl / 2, bw / 2, 0.0),
        (bl + bw / 2, bl / 2, 90.0),
        (bw + bl / 2, bl + bw / 2, 0.0),
        (bw / 2, bw + bl / 2, 90.0),
    ]
    boxes = [Box(i * side + x, j * side + y, a) for j in range(ny) for i in range(nx) for x, y, a in unit]
    return _centred(boxes, nx * side, ny * side, length, width)


def split_row(length: float, width: float, bl: float, bw: float, limit: int = BOXES_MAX) -> list[Box]:
    """Rows along x, every second row shifted half a box (one box fewer): the joints of one row are
    split by the boxes of the next, as bricks in a wall; centred."""
    rows, full = _fit(width, bw), _fit(length, bl)
    shifted = _fit(length - bl / 2, bl)
    _limited((rows + 1) // 2 * full + rows // 2 * max(shifted, 0), limit)
    boxes = []
    for j in range(rows):
        count, x0 = (full, 0.0) if j % 2 == 0 else (shifted, bl / 2)
        boxes.extend(Box(x0 + (i + 0.5) * bl, (j + 0.5) * bw, 0.0) for i in range(count))
    extent = max(full * bl, bl / 2 + shifted * bl if shifted else 0.0)  # a shifted row can reach further
    return _centred(boxes, extent, rows * bw, length, width)


FAMILIES = {"column": column, "interlock": interlock, "pinwheel": pinwheel, "split-row": split_row}


def fuller_family(pallet: Pallet, family: str) -> tuple[str, int, int] | None:
    """(the family that fits the most boxes on a layer, its count, the given family's count) where that is more
    than the given family fits; None: none fits more (or the family is not one of FAMILIES)."""
    if family not in FAMILIES:
        return None
    counts = {}
    for name, make in FAMILIES.items():
        try:
            counts[name] = len(make(*pallet.size, pallet.box[0], pallet.box[1]))
        except TooManyBoxes:  # refused where it is used: no hint to take it
            continue
    best = max(counts, key=lambda name: (counts[name], name == family))
    return (best, counts[best], counts[family]) if family in counts and counts[best] > counts[family] else None
