"""A pallet's refusals (frame, overlap, overhang) and warnings (support, frame upside down), by key path."""

from __future__ import annotations

import numpy as np

from codegen import protocol
from codegen.kinds.pallet import checks
from codegen.kinds.pallet.keys import KEYS
from codegen.kinds.pallet.patterns import TooManyBoxes, fuller_family, layout
from codegen.kinds.pallet.room import check_room
from codegen.kinds.pallet.section import BOXES_MAX, Pallet, pallets_of, parse_pallets
from codegen.kinds.pallet.stack import FrameError, layer_top, pallet2base, pattern_of, placements
from codegen.model.robot import check_carried


def named(pallet: Pallet, key: str = "") -> str:
    """A pallet's key as warnings name it: the pallet by its name, as generate's and verify's messages do ("pallet
    'eur' patterns.p1"); a refusal names the key path (pallet[0].patterns.p1) and the file's line."""
    return f"pallet {pallet.name!r}" + (f" {key}" if key else "")


def check_pallet(ctx, pallet: Pallet, path: str) -> list[str]:
    """Fails (ctx.fail: file, key path) on what cannot be stacked; returns the warnings (named by named())."""
    warnings = []
    try:
        frame = pallet2base(pallet.origin, pallet.x_point, pallet.xy_point)
    except FrameError as exc:
        ctx.fail(path, str(exc))
    if frame[2, 2] < 0:
        warnings.append(
            f"{named(pallet, 'frame')}: the pallet's z points down in the base frame (the tool would come from below): "
            "teach xy_point on the other side of the x axis"
        )
    if pallet.pick is not None:
        _check_pick(ctx, pallet, frame, path)
    if pallet.entry_dz < pallet.box[2]:
        ctx.fail(
            f"{path}.entry_dz",
            f"{pallet.entry_dz:g} mm above the target is less than the box's height ({pallet.box[2]:g} mm, box): "
            f"at the entry the carried box's bottom would be {pallet.box[2] - pallet.entry_dz:g} mm below the tops "
            f"of the boxes already in the layer (entry_dz >= {pallet.box[2]:g})",
        )
    clear_of_q = pallet.box[2] + pallet.transit_clearance_mm
    if pallet.mode == "unstack" and pallet.pick_lift < clear_of_q:
        ctx.fail(
            f"{path}.pick_lift",
            f"{pallet.pick_lift:g} mm: unstacking, the program waits above Q for Q clear with a box in the gripper, "
            f"whose bottom would be {clear_of_q - pallet.pick_lift:g} mm too low to clear a box still lying at Q "
            f"(pick_lift >= the box's height + transit_clearance_mm = {clear_of_q:g})",
        )
    footprint = pallet.box[:2]
    layouts = {}
    for name in pallet.patterns:
        where = f"{path}.patterns.{name}"
        try:
            boxes = layout(pallet, name)
        except TooManyBoxes as exc:
            ctx.fail(
                where,
                f"{exc.count} boxes of {footprint[0]:g} x {footprint[1]:g} mm make this family's layer; at most "
                f"{BOXES_MAX} a stack (verify runs the whole stack, generate solves each of its moves for every arm)",
            )
        if not boxes:
            ctx.fail(where, f"no box of {footprint[0]:g} x {footprint[1]:g} mm fits this family on the pallet")
        for i, j, area in checks.overlaps(boxes, footprint):
            ctx.fail(where, f"boxes {i + 1} and {j + 1} overlap ({area:.1f} mm^2)")
        for i, beyond in checks.overhangs(boxes, footprint, pallet.size):
            if beyond > pallet.overhang_mm + 1e-6:
                ctx.fail(
                    where,
                    f"box {i + 1} reaches {beyond:.1f} mm beyond the pallet's edge "
                    f"(overhang_mm allows {pallet.overhang_mm:g})",
                )
        layouts[name] = boxes
    _check_counts(ctx, pallet, path, layouts)
    _check_zone(ctx, pallet, path)  # every box's poses: once the stack is known to be within BOXES_MAX
    warnings.extend(_support_warning(pallet, layouts))
    warnings.extend(_family_hints(pallet))
    return warnings


def _support_warning(pallet: Pallet, layouts: dict) -> list[str]:
    """One warning for the pallet: each pair of patterns (the first layer it stands at) whose upper boxes rest on
    less than support_min of their bottom, with those boxes."""
    seen, parts = set(), []
    for layer in range(2, pallet.layers + 1):
        below, above = pallet.cycle[(layer - 2) % len(pallet.cycle)], pallet.cycle[(layer - 1) % len(pallet.cycle)]
        if (below, above) in seen:
            continue
        seen.add((below, above))
        shares = checks.support(layouts[above], layouts[below], pallet.box[:2])
        weak = [(i, s) for i, s in enumerate(shares) if s < pallet.support_min - 1e-9]
        if weak:
            listed = ", ".join(f"box {i + 1} {s:.0%}" for i, s in weak[:8]) + (" ..." if len(weak) > 8 else "")
            parts.append(f"layer {layer} ({above} on {below}): {listed}")
    if not parts:
        return []
    return [
        f"{named(pallet)}: boxes that rest on less than support_min {pallet.support_min:.0%} of their bottom on the "
        f"layer below: {'; '.join(parts)}"
    ]


def _family_hints(pallet: Pallet) -> list[str]:
    """A hint per generated family the patterns use where another family fits more boxes on a layer."""
    out, seen = [], set()
    for name, spec in pallet.patterns.items():
        family = getattr(spec, "family", None)
        fuller = None if family in seen else fuller_family(pallet, family)
        seen.add(family)
        if fuller is not None:
            other, more, fewer = fuller
            out.append(
                f"{named(pallet, f'patterns.{name}')}: family {other!r} fits {more} boxes a layer, {family!r} {fewer} "
                "(a hint: keep it where its layers hold together better)"
            )
    return out


def _check_pick(ctx, pallet: Pallet, frame: np.ndarray, path: str) -> None:
    """Q (a box's top where boxes come and go) not over the pallet within the full stack's height: a box at Q would
    stand in the stack, and every move to or from Q would pass through it."""
    x, y, z = (np.linalg.inv(frame) @ pallet.pick.matrix()[:, 3])[:3]
    reach = pallet.overhang_mm
    over = -reach <= x <= pallet.size[0] + reach and -reach <= y <= pallet.size[1] + reach
    top = layer_top(pallet, pallet.layers)
    if over and z - pallet.box[2] < top:
        ctx.fail(
            f"{path}.pick",
            f"Q is over the pallet (at x {x:.1f}, y {y:.1f} mm on its {pallet.size[0]:g} x {pallet.size[1]:g} mm) "
            f"and a box there reaches down to {z - pallet.box[2]:.1f} mm above the deck, below the full stack's top "
            f"({top:g} mm): the boxes would meet; teach Q beside the pallet",
        )


def _check_zone(ctx, pallet: Pallet, path: str) -> None:
    """The blending zone fits every segment it blends: at most half of each path the arm passes a pose on (the lift
    above Q, entry to approach, approach to target, target to retreat, retreat to entry; the sheet's lift and its
    entry), so the arm reaches each exact stop along its own line."""
    if pallet.zone_mm == 0:
        return
    segments = [("the lift above Q (pick_lift)", pallet.pick_lift)]
    if pallet.slip_pick is not None:
        segments += [("the lift above the sheet stack (slip_sheet.lift)", pallet.slip_lift)]
        segments += [("a slip sheet's entry above it (entry_dz)", pallet.entry_dz)]
    for p in placements(pallet):
        where = f"layer {p.layer} box {p.number}"
        for name, a, b in (("entry to approach", p.entry, p.approach), ("approach to target", p.approach, p.target)):
            segments.append((f"{where}: {name}", float(np.linalg.norm(b[:3, 3] - a[:3, 3]))))
        for name, a, b in (("target to retreat", p.target, p.retreat), ("retreat to entry", p.retreat, p.entry)):
            segments.append((f"{where}: {name}", float(np.linalg.norm(b[:3, 3] - a[:3, 3]))))
    name, shortest = min(segments, key=lambda s: s[1])
    if pallet.zone_mm > shortest / 2 + 1e-9:
        ctx.fail(
            f"{path}.zone_mm",
            f"{pallet.zone_mm:g} mm is more than half of the {shortest:.1f} mm of {name}: the arm would blend past "
            f"the next pose (zone_mm <= {shortest / 2:.1f})",
        )


def _check_counts(ctx, pallet: Pallet, path: str, layouts: dict) -> None:
    """The patterns together and the whole stack within BOXES_MAX (each pattern is, once made)."""
    together = sum(len(boxes) for boxes in layouts.values())
    if together > BOXES_MAX:
        ctx.fail(f"{path}.patterns", f"{together} boxes in the patterns together; at most {BOXES_MAX}")
    stack = sum(len(layouts[pattern_of(pallet, layer)]) for layer in range(1, pallet.layers + 1))
    if stack > BOXES_MAX:
        ctx.fail(
            f"{path}.layers",
            f"{pallet.layers} layers of the cycle's patterns make {stack} boxes; at most {BOXES_MAX} a stack "
            "(verify runs the whole stack in the interpreter, generate solves each of its moves for every arm)",
        )


def frame_matrix(pallet: Pallet) -> np.ndarray:
    return pallet2base(pallet.origin, pallet.x_point, pallet.xy_point)


def checked_pallets(ctx, data: dict, cell) -> tuple[Pallet, ...]:
    """The file's [[pallet]] tables, validated and checked; the warnings go to ctx."""
    pallets = parse_pallets(ctx, data, cell)
    for i, pallet in enumerate(pallets):
        ctx.warnings.extend(f"{ctx.source}: {w}" for w in check_pallet(ctx, pallet, f"pallet[{i}]"))
        check_room(ctx, pallet, f"pallet[{i}]", cell.world)
    return pallets


class SectionPart(protocol.Section):
    """The [[pallet]] tables, each checked (its patterns, its zone, its counts), and the cell's [cell.io] they need."""

    keys = KEYS

    def parse(self, ctx, data: dict, cell) -> tuple[Pallet, ...] | None:
        return checked_pallets(ctx, data, cell) or None

    def standalone(self, data: dict) -> bool:
        return bool(data.get("pallet"))

    def check(self, ctx, cell) -> None:
        if pallets_of(cell) and (cell.io is None or not cell.io.feedback):
            ctx.fail(
                "cell.io", "a cell with [[pallet]] needs [cell.io] with feedback: the gripper's output and its sensor"
            )
        for i, pallet in enumerate(pallets_of(cell)):
            check_carried(ctx, cell.robot, pallet.box_mass_kg, f"pallet[{i}].box_mass_kg")
