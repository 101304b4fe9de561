"""What a pallet path's clearance refusal suggests when the arm, the tool or the box comes too near a stack: the fix
that follows the move (the way home's swings, a transit over the stack), naming the keys."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from codegen.decimals import format_literal
from codegen.kinds.pallet.cycle import SAFE_NAME
from codegen.kinds.pallet.section import Pallet
from codegen.kinds.pallet.stack import layer_top, pallet2base

WAY_HOME = " the way home from "  # in the way home's moves' names (codegen/kinds/pallet/scene.py)
SWINGS = ("transit", "over Q")  # a cycle's joint moves at the transit height over the layer worked


def _top_z(pallet: Pallet, layers: int | None = None) -> float:
    """The top of the stack's layers (None: the full stack) over the pallet's origin, as base z, mm."""
    frame = pallet2base(pallet.origin, pallet.x_point, pallet.xy_point)
    top = layer_top(pallet, pallet.layers if layers is None else layers)
    return float((frame @ np.array([0.0, 0.0, top, 1.0]))[2])


def _mm(value: float) -> str:
    return f"{format_literal(value, 1)} mm"


@dataclass(frozen=True)
class StackFix:
    """The pallet's fix for a move of its paths that comes too near a pallet's stack (codegen.world.proof.Path.fix);
    None where the move or the solid is not one it knows a fix for (the proof's own then)."""

    pallet: Pallet
    pallets: tuple[str, ...]  # the cell's pallets' names: whose stacks they are

    def text(self, cell, path, move, other: str) -> str | None:
        owner = self._stack_of(other)
        if owner is None:
            return None
        name = move.where.split(f"pallet {self.pallet.name!r} ", 1)[-1]
        way_home = WAY_HOME in f" {name}"
        # the way home's joint moves: above the pallet's centre, then home
        swing = name.rsplit(": ", 1)[-1] in (SAFE_NAME, "home") if way_home else name.endswith(SWINGS)
        if owner != self.pallet.name:  # another pallet's stack: the two pallets' keys
            return self._other_stack(cell, owner) if swing else None
        if way_home:
            return self._way_home(cell, path) if swing else None
        # a box's own way in and out of its place is the pallet's sweep check's (scene.py, _own_descent): the proof
        # does not measure it against its stack, so no fix of that kind is made here
        return self._transit() if name.endswith(SWINGS) else None

    def _stack_of(self, other: str) -> str | None:
        """The pallet whose stack (or pallet) the solid is, None: another solid (its pick place included)."""
        for name in self.pallets:
            if other == f"pallet {name}" or (other.startswith(f"pallet {name}: ") and not other.endswith("pick place")):
                return name
        return None

    def _keys(self) -> str:
        p = self.pallet
        return (
            f"raise the transit height (transit_clearance_mm of pallet {p.name!r}: {p.transit_clearance_mm:g} mm) "
            f"or lower the stack (layers: {p.layers})"
        )

    def _other_stack(self, cell, owner: str) -> str:
        """A swing of this pallet's moves into another pallet's stack (the transit height is over the layer worked
        here, the way home's over every full stack: the other stack stands higher where the move passes it)."""
        p, other = self.pallet, next(q for q in cell.sections["pallet"] if q.name == owner)
        low = _top_z(p, 1) + p.transit_clearance_mm  # the carried box's bottom at the lowest transit
        return (
            f"the move swings into the stack of pallet {owner!r} (full: {other.layers} layers, its top at z = "
            f"{_mm(_top_z(other))}), while the transit of pallet {p.name!r} holds the box's bottom as low as z = "
            f"{_mm(low)} (over its layer 1): raise that transit (transit_clearance_mm of pallet {p.name!r}: "
            f"{p.transit_clearance_mm:g} mm) over the other stack, lower the other stack (layers of pallet {owner!r}: "
            f"{other.layers}), or place the two pallets farther apart ([[pallet]] frame) so that the arm does not "
            "pass over the other"
        )

    def _transit(self) -> str:
        return (
            f"the move swings over the stack at the transit height, transit_clearance_mm above the top of the layer "
            f"worked (the box's bottom, or the tool's end without one): {self._keys()}"
        )

    def _way_home(self, cell, path) -> str:
        """The way home after a stop: up to the transit height over the full stack, then joint moves above the
        pallet's centre and home; where the home holds the box lower than the stack's top, the home is named too."""
        p = self.pallet
        top = _top_z(p)
        robot = cell.robot
        home = robot.home[path.target]
        at_home = float((robot.arms[path.target].kin.fk(np.asarray(home, dtype=float)) @ robot.tool.tcp2flange)[2, 3])
        shown = f"[cell.robot.home] {path.target} = [{', '.join(f'{v:g}' for v in home)}]"
        low = at_home - p.box[2] < top
        then = (
            f"; the home {shown} holds the box's bottom at z = {_mm(at_home - p.box[2])}, below the full stack's top "
            f"(z = {_mm(top)}): give the arm a home above it or away from the pallet"
            if low
            else f", or give the arm another home than {shown}"
        )
        return (
            f"after a stop the way home lifts the box to the transit height over the full stack (its top at z = "
            f"{_mm(top)}) and swings it above the pallet's centre and home in joint moves: {self._keys()}{then}"
        )
