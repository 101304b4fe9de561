"""Where a pallet stands in the cell, refused at load by its keys: its top clear of the floor, its full stack clear
of the solids [cell.world] declares (a ceiling, a fence, a machine)."""

from __future__ import annotations

import numpy as np

from codegen.decimals import format_literal
from codegen.kinds.pallet.section import Pallet
from codegen.kinds.pallet.stack import layer_top, pallet2base

# A stack that only touches a solid is not in it: a mat lying on a table declared as a solid has its taught top on
# the table's, within what teaching a point by touch gives (a fraction of a millimetre); deeper than this it is in
TOUCH_MM = 1.0
# a EUR pallet's height (EN 13698-1): how far above the floor a pallet's top stands, for the fix's example
EUR_PALLET_MM = 144.0


def top_corners(pallet: Pallet) -> np.ndarray:
    """The pallet's top (the frame's z = 0 over its size): its four corners in the base frame, 4 x 3 (mm)."""
    length, width = pallet.size
    frame = pallet2base(pallet.origin, pallet.x_point, pallet.xy_point)
    local = np.array([[0.0, 0.0, 0.0, 1.0], [length, 0.0, 0.0, 1.0], [0.0, width, 0.0, 1.0], [length, width, 0.0, 1.0]])
    return (local @ frame.T)[:, :3]


def check_floor(ctx, pallet: Pallet, path: str, world) -> None:
    """The pallet's top at least the cell's clearance above the floor (world: [cell.world]): a box carried onto or
    off the first layer (and the way home after a stop there) passes the floor no nearer than the pallet's top, which
    every move keeps the clearance from; a top lower than that stands the pallet in the floor (or on it)."""
    top = float(top_corners(pallet)[:, 2].min())
    floor, clearance = float(world.floor_z_mm), float(world.clearance_mm)
    if top - floor >= clearance:
        return
    gap = round(top - floor, 1)
    where = "on" if gap == 0 else f"{_mm(-gap)} below" if gap < 0 else f"{_mm(gap)} above"
    ctx.fail(
        f"{path}.frame",
        f"pallet {pallet.name!r} stands {'in' if gap <= 0 else 'too near'} the floor: its top (the plane of frame's "
        f"origin, x_point and xy_point) is at z = {_mm(top)} at its lowest corner, {where} the floor at z = "
        f"{floor:g} mm (cell.world.floor_z_mm); a box put on its first layer would come within the clearance of "
        f"{clearance:g} mm (cell.world.clearance_mm) of the floor. Teach the frame's points on the pallet's top "
        f"surface (a pallet's top stands its height above the floor, a EUR pallet's {EUR_PALLET_MM:g} mm), or set "
        f"cell.world.floor_z_mm to the floor's height (at most {_mm(top - clearance)})",
    )


def _mm(value: float) -> str:
    return f"{format_literal(value, 1)} mm"


def stack_box(pallet: Pallet, layers: int):
    """The stack of the pallet's first `layers` layers as a solid (codegen.world.solids.Box): the pallet's area and
    its overhang, from the top of the pallet to the top of the last layer."""
    from codegen.world.solids import Box

    length, width = pallet.size
    height = layer_top(pallet, layers)
    grow = 2 * pallet.overhang_mm
    centre = np.eye(4)
    centre[:3, 3] = (length / 2, width / 2, height / 2)
    frame = pallet2base(pallet.origin, pallet.x_point, pallet.xy_point)
    return Box((length + grow, width + grow, height), frame @ centre)


def check_solids(ctx, pallet: Pallet, path: str, world) -> None:
    """The full stack clear of every solid [cell.world] declares: a stack that would rise into a ceiling, a fence or
    a machine is refused at `layers` with how deep and how many layers fit."""
    if not world.solids:
        return
    from codegen.world.solids import bounding_box, separation_bound, shape_of

    eye = np.eye(4)
    whole = stack_box(pallet, pallet.layers)
    for name, spec in world.solids.items():
        solid = shape_of(spec)
        # a bound the stack's and the solid's boxes cannot come closer than: no deeper than TOUCH_MM, so the exact
        # distance need not be asked (loading a cell loads the collision library only for a solid at a stack)
        if separation_bound(whole, bounding_box(solid)) > -TOUCH_MM:
            continue
        from codegen.world.engine import distance

        def depth(layers: int, solid=solid) -> float:
            return -distance(stack_box(pallet, layers), eye, solid, eye)[0]

        deepest = depth(pallet.layers)
        if deepest <= TOUCH_MM:
            continue
        fit = next((n for n in range(pallet.layers - 1, 0, -1) if depth(n) <= TOUCH_MM), 0)
        then = (
            f"at most {fit} layer{'s' if fit != 1 else ''} fit below it: lower layers, or move the pallet or the solid"
            if fit
            else "even its first layer is in it: move the pallet (its frame) or the solid"
        )
        ctx.fail(
            f"{path}.layers",
            f"pallet {pallet.name!r}: its full stack ({pallet.layers} layers, "
            f"{layer_top(pallet, pallet.layers):g} mm above the pallet's top) reaches {deepest:.1f} mm into the solid "
            f"{name!r} (cell.world.solids.{name}); {then}",
        )


def check_room(ctx, pallet: Pallet, path: str, world) -> None:
    """The pallet against the floor and the declared solids (world: the cell's [cell.world])."""
    check_floor(ctx, pallet, path, world)
    check_solids(ctx, pallet, path, world)
