"""The pallet kind's geometry for a cell, the same on every target: each pallet's frame, boxes and full cycle."""

# The program writer, the reference's proofs, the scene, verify's cases and judgement and the report read this (the
# target plan, codegen/kinds/pallet/plan.py, starts from it) instead of working the frame and the boxes out again.
# It is kept with the cell (Cell.plans, which a cell made from another by dataclasses.replace starts without) under
# KEY: the kind's name and no target.

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from codegen.kinds.pallet.analysis import frame_matrix
from codegen.kinds.pallet.cycle import Item, PalletCase, items, safe_pose
from codegen.kinds.pallet.kind import KIND
from codegen.kinds.pallet.patterns import Box, layout
from codegen.kinds.pallet.restart import expected
from codegen.kinds.pallet.section import Pallet, pallets_of
from codegen.kinds.pallet.stack import Placement, layer_top, placements

KEY = (KIND.name, None)  # Cell.plans' key: a kind's target plans are (name, target)


@dataclass(frozen=True)
class PalletShape:
    """One pallet of a cell: its frame (pallet2base), each of its cycle's patterns' boxes, every box's placement in
    placing order, what the program does in its order (items), the top of each layer (tops[n], pallet frame, mm;
    tops[0] the deck) and the way home's pose above its centre (safe2base)."""

    pallet: Pallet
    pallet2base: np.ndarray
    layouts: dict[str, tuple[Box, ...]]
    placements: tuple[Placement, ...]
    items: tuple[Item, ...]
    tops: tuple[float, ...]
    safe2base: np.ndarray

    @classmethod
    def of(cls, pallet: Pallet) -> PalletShape:
        pallet2base = frame_matrix(pallet)
        return cls(
            pallet,
            pallet2base,
            {name: layout(pallet, name) for name in dict.fromkeys(pallet.cycle)},
            tuple(placements(pallet)),
            tuple(items(pallet)),
            tuple(layer_top(pallet, n) for n in range(pallet.layers + 1)),
            pallet2base @ safe_pose(pallet),
        )

    @property
    def boxes(self) -> int:
        return len(self.placements)

    def layer_counts(self) -> dict[int, int]:
        """Boxes per layer (1 = bottom)."""
        counts: dict[int, int] = {}
        for p in self.placements:
            counts[p.layer] = counts.get(p.layer, 0) + 1
        return counts


@dataclass(frozen=True)
class Shape:
    """The pallet kind's geometry for one cell: a PalletShape per [[pallet]] in the cell file's order, and the base z
    the way home rises to (the highest of the pallets' safe poses: over any of them, full or not); each pallet's full
    cycle by its name, made where first asked (generate's proofs, verify, the report; not the page)."""

    pallets: tuple[PalletShape, ...]
    cycles: dict = field(default_factory=dict, compare=False, repr=False)

    @property
    def way_up_z(self) -> float:
        return max(float(p.safe2base[2, 3]) for p in self.pallets)

    def of(self, pallet: Pallet) -> PalletShape | None:
        """The shape of one of the cell's pallets (by identity); None: not one of them."""
        return next((p for p in self.pallets if p.pallet is pallet), None)


def shape(cell) -> Shape:
    """The cell's pallet geometry, made once per cell where first asked and kept with it."""
    if KEY not in cell.plans:
        cell.plans[KEY] = Shape(tuple(PalletShape.of(p) for p in pallets_of(cell)))
    return cell.plans[KEY]


def pallet_shape(cell, pallet: Pallet) -> PalletShape:
    """The shape of a pallet of the cell; a pallet that is not one of the cell's (a variant a caller made of one) is
    worked out for itself and not kept."""
    return shape(cell).of(pallet) or PalletShape.of(pallet)


def full_cycle(cell, pallet: Pallet) -> tuple:
    """The moves of a whole stack (or unstack) from its first item, as the reference has them: made once per cell and
    pallet (a pallet not the cell's: worked out for itself, not kept)."""
    held = shape(cell)
    own = held.of(pallet)
    if own is not None and pallet.name in held.cycles:
        return held.cycles[pallet.name]
    moves = tuple(expected(cell, pallet, PalletCase("full", *pallet_shape(cell, pallet).items[0].key)).moves)
    if own is not None:
        held.cycles[pallet.name] = moves
    return moves
