"""Template variables of a stacking program: the pallet's frame, pattern tables and cycle as data, the counters."""

from __future__ import annotations

import math

import numpy as np

from codegen import derived
from codegen.emit import EmitError, Emitter, owned
from codegen.kinds.pallet.analysis import frame_matrix
from codegen.kinds.pallet.cycle import (
    above_pick,
    counters_message,
    empty_message,
    full_message,
    held_message,
    layer_counts,
)
from codegen.kinds.pallet.facts import facts
from codegen.kinds.pallet.patterns import layout
from codegen.kinds.pallet.reach import PICK_KEY, configurations
from codegen.kinds.pallet.section import Pallet, pallets_of
from codegen.kinds.pallet.stack import sides
from codegen.model.cell import TaughtPose
from codegen.poses import zyx_deg_from_rotmat
from codegen.render import configuration_literal

LEVEL_TOL = 1e-9  # a level pallet: its z is the base's z (a dialect without a pose product needs one)


def pallet_file_names(target, pallet_ident: str) -> list[str]:
    return [name.format(pallet=pallet_ident.lower()) for name in facts(target)["files"]]


def counter_registers(target, index: int) -> tuple[int, int] | None:
    """The registers of pallet `index`'s layer and box counters, where the controller keeps them outside
    the program (targets/<t>.toml pallet_registers), else None."""
    first = facts(target).get("registers")
    if first is None:
        return None
    last = facts(target)["registers_max"]
    if first + 2 * index + 1 > last:
        raise EmitError(
            f"{target.name}: pallet {index + 1}'s counters would need registers {first + 2 * index} and "
            f"{first + 2 * index + 1}; the controller's last is {last} ({(last - first + 1) // 2} pallets per cell)"
        )
    return first + 2 * index, first + 2 * index + 1


def counter_names(target, index: int) -> tuple[str, str]:
    """The names of pallet `index`'s layer and box counters (`codegen run --input`, verify)."""
    names, registers = facts(target)["counters"], counter_registers(target, index)
    numbers = {"layer": registers[0], "box": registers[1]} if registers else {}
    return names["layer"].format(**numbers), names["box"].format(**numbers)


def pallet_identifiers(cell, target) -> list[str]:
    """Each pallet's program identifier ("pal_" and its name); the counters' names are taken first, so a
    pallet whose program would be named like a counter is refused (EmitError naming both)."""
    emitter = Emitter(target)
    if cell.stations:  # the vision program's name (and so its files' names)
        emitter.identifier("", cell.name, "the cell's program")
    for index in range(len(pallets_of(cell))):
        for name in counter_names(target, index):
            emitter.reserve(name, f"the pallet counter {name}")
    return [emitter.identifier("pal_", p.name, f"pallet {p.name!r}") for p in pallets_of(cell)]


def pallet_context(cell, pallet: Pallet, index: int, ident: str, target, emitter) -> dict:
    """Numbers in the target's notation: the frame (pallet2base), the patterns of the cycle flattened
    into one table (x, y mm, angle deg counterclockwise; each pattern's first row and count), the
    cycle as pattern numbers, the layer heights, the offsets of entry, approach and retreat, the tool's
    orientation at angle 0, the pick pose and the pose above it, the configuration of each row's entry and
    of the pose above Q (with an arm: chosen at generate time, codegen/pallet/reach.py), the counters' names
    and the stop messages."""
    number = emitter.number
    frame = frame_matrix(pallet)
    frame_xyzabc = _xyzabc(frame)
    named = configurations(cell, pallet, target.name)

    def conf(key) -> dict | None:
        return None if named is None else {**configuration_literal(target, named.values[key]), "named": True}

    names = list(dict.fromkeys(pallet.cycle))  # each pattern once, in the cycle's order
    rows, patterns = [], []
    for name in names:
        boxes = layout(pallet, name)
        patterns.append({"name": emitter.comment(name), "start": len(rows) + 1, "count": len(boxes)})
        rows.extend(
            {
                "x": number(b.x, 4),
                "y": number(b.y, 4),
                "a": number(b.ccw_deg, 4),
                # the x-y part of the approach and the retreat (the cell's, or away from the earlier boxes)
                "ax": number(ax, 4),
                "ay": number(ay, 4),
                "rx": number(rx, 4),
                "ry": number(ry, 4),
                "conf": conf((name, i)),  # the configuration of the box's entry (a joint move)
            }
            for i, (b, ((ax, ay), (rx, ry))) in enumerate(zip(boxes, sides(pallet, boxes), strict=True), start=1)
        )
    level = bool(np.allclose(frame[:3, 2], (0.0, 0.0, 1.0), atol=LEVEL_TOL))
    counts = layer_counts(pallet)
    return {
        "name": emitter.comment(pallet.name),
        "ident": ident,
        "file": ident.lower(),
        "frame": emitter.pose(TaughtPose("frame", tuple(float(v) for v in frame_xyzabc), "xyzabc")),
        "frame_rotation": [[number(v, 9) for v in row] for row in frame[:3, :3]],
        "frame_origin": [number(v, 4) for v in frame[:3, 3]],
        "level": level,
        "frame_turn_deg": number(math.degrees(math.atan2(frame[1, 0], frame[0, 0])), 6),
        "rows": rows,
        "position": owned(derived.printed(target.dialect, "box")["outputs"]),  # a box's x, y on a level pallet
        "patterns": patterns,
        "cycle": [names.index(name) + 1 for name in pallet.cycle],
        "layers": pallet.layers,
        "max_count": max(counts.values()),
        "box_height": number(pallet.box[2], 4),
        "slip_every": pallet.slip_every,
        "slip_thickness": number(pallet.slip_thickness, 4),
        "entry_dz": number(pallet.entry_dz, 4),
        "approach": [number(v, 4) for v in pallet.approach],
        "retreat": [number(v, 4) for v in pallet.retreat],
        "tool_orientation": [number(v, 6) for v in pallet.tool_orientation],
        "tool": emitter.pose(TaughtPose("tool", (0.0, 0.0, 0.0, *pallet.tool_orientation), "xyzabc")),
        "pick": emitter.pose(pallet.pick),
        "pick_above": emitter.pose(TaughtPose("above_q", _xyzabc(above_pick(pallet)), "xyzabc")),
        "pick_lift": number(pallet.pick_lift, 4),
        "pick_conf": conf(PICK_KEY),
        "registers": counter_registers(target, index),
        "auto": pallet.approach_auto,
        "unstack": pallet.mode == "unstack",  # take the boxes off, top layer first, each layer in reverse
        "top_count": counts[pallet.layers],
        "empty": emitter.string(empty_message(pallet)),
        "full": emitter.string(full_message(pallet)),
        "held": emitter.string(held_message(pallet)),
        "bad_counters": emitter.string(counters_message(pallet)),
    }


def _xyzabc(pose) -> tuple[float, ...]:
    return tuple(float(v) for v in (*pose[:3, 3], *zyx_deg_from_rotmat(pose[:3, :3])))


def check_level(pallet: Pallet, target) -> None:
    """A dialect without a pose product places boxes on a level pallet only."""
    if facts(target).get("level_only") and not np.allclose(
        frame_matrix(pallet)[:3, 2], (0.0, 0.0, 1.0), atol=LEVEL_TOL
    ):
        raise EmitError(
            f"pallet {pallet.name!r}: the {target.name} program needs a level pallet (its z the base's z): "
            "the dialect has no pose product to tilt the boxes"
        )
