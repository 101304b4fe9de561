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


def _mm(value: float) -> str:
    return f"{format_literal(value, 1)} mm"


@dataclass(frozen=True)
class StackFix:
    """The pallet's fix for a move of its paths that comes too near a pallet's stack (codegen.world.proof.Path.fix);
    None where the move or the solid is not one it knows a fix for (the proof's own then)."""

    pallet: Pallet
    pallets: tuple[str, ...]  # the cell's pallets' names: whose stacks they are

    def text(self, cell, path, move, other: str) -> str | None:
        if self._stack_of(other) != self.pallet.name:  # another pallet's stack: its own keys are not these
            return None
        name = move.where.split(f"pallet {self.pallet.name!r} ", 1)[-1]
        if WAY_HOME in f" {name}":
            segment = name.rsplit(": ", 1)[-1]  # the way home's joint moves: above the pallet's centre, then home
            return self._way_home(cell, path) if segment in (SAFE_NAME, "home") else None
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

    def _transit(self) -> str:
        return (
            f"the move swings over the stack at the transit height, transit_clearance_mm above the top of the layer "
            f"worked (the box's bottom, or the tool's end without one): {self._keys()}"
        )

    def _way_home(self, cell, path) -> str:
        """The way home after a stop: up to the transit height over the full stack, then joint moves above the
        pallet's centre and home; where the home holds the box lower than the stack's top, the home is named too."""
        p = self.pallet
        frame = pallet2base(p.origin, p.x_point, p.xy_point)
        top = float((frame @ np.array([0.0, 0.0, layer_top(p, p.layers), 1.0]))[2])
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
