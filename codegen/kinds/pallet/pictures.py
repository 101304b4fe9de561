"""One SVG per layer, as people check a pattern before they run it: outline, numbered boxes, label side, approach."""

from __future__ import annotations

import math
from html import escape

from codegen.kinds.pallet.checks import corners, overhangs
from codegen.kinds.pallet.patterns import label_normal
from codegen.kinds.pallet.shape import PalletShape
from codegen.kinds.pallet.stack import pattern_of, sides

WIDTH_PX = 640.0
MARGIN_PX = 40.0
MARK = "<metadata>written by codegen pallet --svg</metadata>"  # in a picture's first lines: one `pallet --svg` replaces
ARROW = '<defs><marker id="arrow" viewBox="0 0 10 10" refX="9" refY="5" markerWidth="6" markerHeight="6" '
# a picture of a codegen that wrote no MARK is known by its arrow's line, codegen's own: it is replaced too
MARKS = (MARK.encode(), ARROW.encode())


def layer_svg(shape: PalletShape, layer: int) -> str:
    """The pallet seen from above (its x to the right, y up); boxes numbered in placing order, the label
    side drawn thick, an arrow for the approach's direction, boxes beyond the edge in red."""
    pallet = shape.pallet
    name = pattern_of(pallet, layer)
    boxes = shape.layouts[name]
    length, width = pallet.size
    reach = max([pallet.overhang_mm, *(mm for _i, mm in overhangs(boxes, pallet.box[:2], pallet.size))])
    scale = (WIDTH_PX - 2 * MARGIN_PX) / (length + 2 * reach)
    height_px = (width + 2 * reach) * scale + 2 * MARGIN_PX + 30

    def px(x: float, y: float) -> tuple[float, float]:
        return (MARGIN_PX + (x + reach) * scale, height_px - MARGIN_PX - (y + reach) * scale)

    over = {i for i, _mm in overhangs(boxes, pallet.box[:2], pallet.size)}
    title = f"{pallet.name}: layer {layer} of {pallet.layers}, pattern {name}, top at z {shape.tops[layer]:g} mm"
    x0, y0 = px(0.0, width)
    out = [
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{WIDTH_PX:.0f}" height="{height_px:.0f}" '
        f'viewBox="0 0 {WIDTH_PX:.0f} {height_px:.0f}" font-family="sans-serif">',
        MARK,
        f"<title>{escape(title)}</title>",
        ARROW + 'orient="auto-start-reverse"><path d="M0,0 L10,5 L0,10 z" fill="#1f5fbf"/></marker></defs>',
        f'<text x="{MARGIN_PX:.0f}" y="22" font-size="14">{escape(title)}</text>',
        f'<rect class="pallet" x="{x0:.1f}" y="{y0:.1f}" width="{length * scale:.1f}" height="{width * scale:.1f}" '
        'fill="#f3e3c3" stroke="#6b4f1d" stroke-width="2"/>',
    ]
    approaches = [approach for approach, _retreat in sides(pallet, boxes)]  # each box's x-y approach offset
    for i, box in enumerate(boxes):
        shape = corners(box, *pallet.box[:2])
        points = " ".join(f"{u:.1f},{v:.1f}" for u, v in (px(*c) for c in shape))
        colour = "#d62828" if i in over else "#333333"
        out.append(
            f'<polygon class="box{" overhang" if i in over else ""}" data-box="{i + 1}" points="{points}" '
            f'fill="#fff8e7" stroke="{colour}" stroke-width="1.5"/>'
        )
        nx, ny = label_normal(box)  # the label's edge: the two corners on that side
        side = [c for c in shape if (c[0] - box.x) * nx + (c[1] - box.y) * ny > 1e-9]
        (lx1, ly1), (lx2, ly2) = px(*side[0]), px(*side[1])
        out.append(
            f'<line class="label" x1="{lx1:.1f}" y1="{ly1:.1f}" x2="{lx2:.1f}" y2="{ly2:.1f}" '
            'stroke="#2a9d8f" stroke-width="4"/>'
        )
        cx, cy = px(box.x, box.y)
        ax, ay = approaches[i]
        arrow = math.hypot(ax, ay)
        if arrow > 0:  # the approach comes from target + offset: the arrow points along the way in
            size = min(pallet.box[:2]) * scale * 0.35
            sx, sy = cx + ax / arrow * size, cy - ay / arrow * size
            out.append(
                f'<line class="approach" x1="{sx:.1f}" y1="{sy:.1f}" x2="{cx + (sx - cx) * 0.2:.1f}" '
                f'y2="{cy + (sy - cy) * 0.2:.1f}" stroke="#1f5fbf" stroke-width="1.5" marker-end="url(#arrow)"/>'
            )
        out.append(
            f'<text class="number" x="{cx:.1f}" y="{cy + 5:.1f}" font-size="14" text-anchor="middle">{i + 1}</text>'
        )
    out.append("</svg>")
    return "\n".join(out) + "\n"


def pictures(shape: PalletShape) -> dict[str, str]:
    """File name -> SVG for every layer."""
    name = shape.pallet.name
    return {f"{name}_layer{n:02d}.svg": layer_svg(shape, n) for n in range(1, shape.pallet.layers + 1)}
